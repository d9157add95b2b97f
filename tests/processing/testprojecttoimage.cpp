// geostation:project_to_image called through the processing registry, as the
// toolbox and models call it. Expected pixels are hand-computed from the
// conventions for a nadir camera without distortion.
#include <QTemporaryDir>
#include <QtTest/QtTest>

#include <gdal.h>
#include <ogr_api.h>
#include <ogr_srs_api.h>

#include <qgsapplication.h>
#include <qgscoordinatetransform.h>
#include <qgsprocessingalgorithm.h>
#include <qgsprocessingcontext.h>
#include <qgsprocessingfeedback.h>
#include <qgsprocessingregistry.h>
#include <qgsprocessingutils.h>
#include <qgsproject.h>
#include <qgsrasterlayer.h>
#include <qgsrasterdataprovider.h>
#include <qgstest.h>
#include <qgsvectorlayer.h>

#include "geostationprovider.h"
#include "processingtestutils.h"

namespace
{
  // A 400 x 300 nadir camera, f = 1000 px, principal point at the image
  // centre, 1000 m above ground at Z = 100: one pixel is one metre, and
  // col = 200 + dX, row = 150 - dY.
  const char *kBlockTemplate = R"json({
    "format": "geostation-block", "version": 1, "crs": "%1",
    "cameras": [{"id": "nadir", "width": 400, "height": 300, "f": 1000.0, "cx": 200.0, "cy": 150.0}],
    "stations": [{"id": "S1", "time": "2025-05-01T10:00:00Z"}],
    "images": [{"id": "N1", "camera": "nadir", "station": "S1", "path": "images/N1.tif",
                "X": 500000.0, "Y": 4400000.0, "Z": 1100.0, "omega": 0, "phi": 0, "kappa": 0},
               {"id": "N2", "camera": "nadir", "station": "S1", "path": "images/N2.tif"}]
  })json";
} // namespace

class TestProjectToImage : public QObject
{
    Q_OBJECT

  private slots:
    void initTestCase();
    void cleanupTestCase();
    void registrationIsIdempotent();
    void projectsHandComputedPixels();
    void transformsFromTheLayerCrs();
    void multipointsKeepAllParts();
    void geopackageOutputHasNoCrs();
    void rawImageSitsInPixelSpace();
    void badInputFailsWithOneSentenceAndNoOutput_data();
    void badInputFailsWithOneSentenceAndNoOutput();

  private:
    QString writeBlock( const QString &name, const QString &text );
    void writeImage( const QString &relativePath, int width, int height );
    QgsVectorLayer *pointLayer( const QString &type, const QString &crs, const QList<QPair<QString, QString>> &wktAndName );
    QVariantMap run( const QVariantMap &parameters, bool *ok, RecordingFeedback *feedback );

    QTemporaryDir mDir;
    QString mBlockPath;
    QgsProcessingContext mContext;
};

void TestProjectToImage::initTestCase()
{
  QVERIFY( mDir.isValid() );
  QVERIFY( registerGeoStationProvider() );
  mBlockPath = writeBlock( QStringLiteral( "run.geostation.json" ), QString::fromLatin1( kBlockTemplate ).arg( QStringLiteral( "EPSG:32617" ) ) );
  writeImage( QStringLiteral( "images/N1.tif" ), 400, 300 );
  mContext.setProject( QgsProject::instance() );
}

void TestProjectToImage::cleanupTestCase()
{
  QgsProject::instance()->clear();
}

QString TestProjectToImage::writeBlock( const QString &name, const QString &text )
{
  const QString path = mDir.filePath( name );
  QFile file( path );
  file.open( QIODevice::WriteOnly );
  file.write( text.toUtf8() );
  return path;
}

void TestProjectToImage::writeImage( const QString &relativePath, int width, int height )
{
  QDir( mDir.path() ).mkpath( QFileInfo( mDir.filePath( relativePath ) ).path() );
  GDALAllRegister();
  GDALDatasetH ds = GDALCreate( GDALGetDriverByName( "GTiff" ), mDir.filePath( relativePath ).toUtf8().constData(), width, height, 1, GDT_Byte, nullptr );
  QVERIFY( ds );
  GDALClose( ds );
}

QgsVectorLayer *TestProjectToImage::pointLayer( const QString &type, const QString &crs, const QList<QPair<QString, QString>> &wktAndName )
{
  auto *layer = new QgsVectorLayer( QStringLiteral( "%1?crs=%2&field=name:string" ).arg( type, crs ), QStringLiteral( "points" ), QStringLiteral( "memory" ) );
  for ( const auto &item : wktAndName )
  {
    QgsFeature f( layer->fields() );
    f.setGeometry( QgsGeometry::fromWkt( item.first ) );
    f.setAttribute( 0, item.second );
    layer->dataProvider()->addFeature( f );
  }
  QgsProject::instance()->addMapLayer( layer );
  return layer;
}

QVariantMap TestProjectToImage::run( const QVariantMap &parameters, bool *ok, RecordingFeedback *feedback )
{
  const QgsProcessingAlgorithm *registered = QgsApplication::processingRegistry()->algorithmById( QStringLiteral( "geostation:project_to_image" ) );
  if ( !registered )
  {
    *ok = false;
    return QVariantMap();
  }
  std::unique_ptr<QgsProcessingAlgorithm> algorithm( registered->create() );
  return algorithm->run( parameters, mContext, feedback, ok );
}

void TestProjectToImage::registrationIsIdempotent()
{
  QVERIFY( !registerGeoStationProvider() );
  QVERIFY( QgsApplication::processingRegistry()->providerById( QStringLiteral( "geostation" ) ) );
  QCOMPARE( QgsApplication::processingRegistry()->providers().count( QgsApplication::processingRegistry()->providerById( QStringLiteral( "geostation" ) ) ), 1 );
  QVERIFY( QgsApplication::processingRegistry()->algorithmById( QStringLiteral( "geostation:project_to_image" ) ) );
}

void TestProjectToImage::projectsHandComputedPixels()
{
  QgsVectorLayer *layer = pointLayer( QStringLiteral( "PointZ" ), QStringLiteral( "EPSG:32617" ),
  {
    { QStringLiteral( "PointZ (500010 4400020 100)" ), QStringLiteral( "pole" ) },
    { QStringLiteral( "PointZ (499900.5 4399950 100)" ), QStringLiteral( "hydrant" ) },
    { QStringLiteral( "PointZ (500000 4400000 600)" ), QStringLiteral( "halfway" ) },
    { QStringLiteral( "PointZ (500300 4400000 100)" ), QStringLiteral( "outside" ) },
    { QStringLiteral( "PointZ (500000 4400000 1200)" ), QStringLiteral( "above camera" ) },
  } );
  bool ok = false;
  RecordingFeedback feedback;
  const QVariantMap result = run( { { "BLOCK", mBlockPath }, { "IMAGE", "N1" }, { "INPUT", layer->id() }, { "OUTPUT", QgsProcessing::TEMPORARY_OUTPUT } }, &ok, &feedback );
  QVERIFY2( ok, qPrintable( feedback.errors.join( '\n' ) ) );
  QCOMPARE( result.value( "PROJECTED_COUNT" ).toInt(), 4 );
  QCOMPARE( result.value( "IN_FRAME_COUNT" ).toInt(), 3 );
  QCOMPARE( result.value( "BEHIND_CAMERA_COUNT" ).toInt(), 1 );

  QgsVectorLayer *out = qobject_cast<QgsVectorLayer *>( QgsProcessingUtils::mapLayerFromString( result.value( "OUTPUT" ).toString(), mContext ) );
  QVERIFY( out );
  QCOMPARE( out->wkbType(), QgsWkbTypes::Point );
  QCOMPARE( out->fields().names(), QStringList( { "name", "col", "row", "depth_m", "in_frame", "visible", "status", "message" } ) );

  QMap<QString, QgsFeature> byName;
  QgsFeature f;
  QgsFeatureIterator it = out->getFeatures();
  while ( it.nextFeature( f ) )
    byName.insert( f.attribute( "name" ).toString(), f );
  QCOMPARE( byName.size(), 5 );

  // pole: dX = 10, dY = 20 -> col 210, row 130 -> (x, y) = (210, -130)
  const QgsPointXY pole = byName["pole"].geometry().asPoint();
  QGSCOMPARENEAR( pole.x(), 210.0, 1e-9 );
  QGSCOMPARENEAR( pole.y(), -130.0, 1e-9 );
  QGSCOMPARENEAR( byName["pole"].attribute( "col" ).toDouble(), 210.0, 1e-9 );
  QGSCOMPARENEAR( byName["pole"].attribute( "row" ).toDouble(), 130.0, 1e-9 );
  QGSCOMPARENEAR( byName["pole"].attribute( "depth_m" ).toDouble(), 1000.0, 1e-9 );
  QVERIFY( byName["pole"].attribute( "in_frame" ).toBool() );
  QVERIFY( byName["pole"].attribute( "visible" ).toBool() );

  // hydrant: dX = -99.5, dY = -50 -> col 100.5, row 200 (the centre of pixel (100, 199) is 100.5, 199.5)
  QGSCOMPARENEAR( byName["hydrant"].geometry().asPoint().x(), 100.5, 1e-9 );
  QGSCOMPARENEAR( byName["hydrant"].geometry().asPoint().y(), -200.0, 1e-9 );

  // halfway up: 500 m below the camera, on the axis -> principal point
  QGSCOMPARENEAR( byName["halfway"].geometry().asPoint().x(), 200.0, 1e-9 );
  QGSCOMPARENEAR( byName["halfway"].attribute( "depth_m" ).toDouble(), 500.0, 1e-9 );

  // outside: col = 500 > 400: projected but not in the frame
  QGSCOMPARENEAR( byName["outside"].geometry().asPoint().x(), 500.0, 1e-9 );
  QVERIFY( !byName["outside"].attribute( "in_frame" ).toBool() );
  QVERIFY( !byName["outside"].attribute( "visible" ).toBool() );

  QCOMPARE( byName["pole"].attribute( "status" ).toString(), QStringLiteral( "ok" ) );
  QCOMPARE( byName["outside"].attribute( "status" ).toString(), QStringLiteral( "ok" ) ); // projected, out of the frame
  // above the camera: behind it, never projected
  QCOMPARE( byName["above camera"].attribute( "status" ).toString(), QStringLiteral( "behind_camera" ) );
  QVERIFY( !byName["above camera"].hasGeometry() );
  QVERIFY( !byName["above camera"].attribute( "in_frame" ).toBool() );
  QVERIFY( byName["above camera"].attribute( "col" ).isNull() );
  QGSCOMPARENEAR( byName["above camera"].attribute( "depth_m" ).toDouble(), -100.0, 1e-9 );
}

void TestProjectToImage::transformsFromTheLayerCrs()
{
  const QgsCoordinateTransform toWgs84( QgsCoordinateReferenceSystem( "EPSG:32617" ), QgsCoordinateReferenceSystem( "EPSG:4326" ), QgsProject::instance() );
  const QgsPointXY lonLat = toWgs84.transform( QgsPointXY( 500010, 4400020 ) );
  QgsVectorLayer *layer = pointLayer( QStringLiteral( "PointZ" ), QStringLiteral( "EPSG:4326" ),
  { { QStringLiteral( "PointZ (%1 %2 100)" ).arg( lonLat.x(), 0, 'f', 12 ).arg( lonLat.y(), 0, 'f', 12 ), QStringLiteral( "pole" ) } } );
  bool ok = false;
  RecordingFeedback feedback;
  const QVariantMap result = run( { { "BLOCK", mBlockPath }, { "IMAGE", "N1" }, { "INPUT", layer->id() }, { "OUTPUT", QgsProcessing::TEMPORARY_OUTPUT } }, &ok, &feedback );
  QVERIFY2( ok, qPrintable( feedback.errors.join( '\n' ) ) );
  QgsVectorLayer *out = qobject_cast<QgsVectorLayer *>( QgsProcessingUtils::mapLayerFromString( result.value( "OUTPUT" ).toString(), mContext ) );
  QgsFeature f;
  QVERIFY( out->getFeatures().nextFeature( f ) );
  QGSCOMPARENEAR( f.geometry().asPoint().x(), 210.0, 1e-5 );
  QGSCOMPARENEAR( f.geometry().asPoint().y(), -130.0, 1e-5 );
}

void TestProjectToImage::multipointsKeepAllParts()
{
  QgsVectorLayer *layer = pointLayer( QStringLiteral( "MultiPointZ" ), QStringLiteral( "EPSG:32617" ),
  { { QStringLiteral( "MultiPointZ ((500010 4400020 100), (500000 4400000 100))" ), QStringLiteral( "pair" ) } } );
  bool ok = false;
  RecordingFeedback feedback;
  const QVariantMap result = run( { { "BLOCK", mBlockPath }, { "IMAGE", "N1" }, { "INPUT", layer->id() }, { "OUTPUT", QgsProcessing::TEMPORARY_OUTPUT } }, &ok, &feedback );
  QVERIFY2( ok, qPrintable( feedback.errors.join( '\n' ) ) );
  QgsVectorLayer *out = qobject_cast<QgsVectorLayer *>( QgsProcessingUtils::mapLayerFromString( result.value( "OUTPUT" ).toString(), mContext ) );
  QCOMPARE( out->wkbType(), QgsWkbTypes::MultiPoint );
  QgsFeature f;
  QVERIFY( out->getFeatures().nextFeature( f ) );
  QCOMPARE( f.geometry().asWkt( 6 ), QStringLiteral( "MultiPoint ((210 -130),(200 -150))" ) );
}

void TestProjectToImage::geopackageOutputHasNoCrs()
{
  // Image space has no CRS: the written file must say "Cartesian, no CRS"
  // (QGIS then places it like a raster without georeferencing, x = col, y = -row).
  QgsVectorLayer *layer = pointLayer( QStringLiteral( "PointZ" ), QStringLiteral( "EPSG:32617" ), { { QStringLiteral( "PointZ (500010 4400020 100)" ), QStringLiteral( "pole" ) } } );
  const QString outputPath = mDir.filePath( QStringLiteral( "pixels.gpkg" ) );
  bool ok = false;
  RecordingFeedback feedback;
  run( { { "BLOCK", mBlockPath }, { "IMAGE", "N1" }, { "INPUT", layer->id() }, { "OUTPUT", outputPath } }, &ok, &feedback );
  QVERIFY2( ok, qPrintable( feedback.errors.join( '\n' ) ) );
  GDALDatasetH ds = GDALOpenEx( outputPath.toUtf8().constData(), GDAL_OF_VECTOR, nullptr, nullptr, nullptr );
  QVERIFY( ds );
  OGRLayerH ogrLayer = GDALDatasetGetLayer( ds, 0 );
  QVERIFY( ogrLayer );
  OGRSpatialReferenceH srs = OGR_L_GetSpatialRef( ogrLayer );
  QVERIFY( srs );
  QCOMPARE( QString( OSRGetName( srs ) ), QStringLiteral( "Undefined Cartesian SRS" ) );
  OGRLayerH srsIds = GDALDatasetExecuteSQL( ds, "SELECT srs_id FROM gpkg_contents", nullptr, nullptr );
  OGRFeatureH row = OGR_L_GetNextFeature( srsIds );
  QCOMPARE( OGR_F_GetFieldAsInteger( row, 0 ), -1 ); // "Undefined Cartesian SRS"
  OGR_F_Destroy( row );
  GDALDatasetReleaseResultSet( ds, srsIds );
  QCOMPARE( OGR_L_GetFeatureCount( ogrLayer, 1 ), 1LL );
  OGRFeatureH feature = OGR_L_GetNextFeature( ogrLayer );
  OGRGeometryH geometry = OGR_F_GetGeometryRef( feature );
  QGSCOMPARENEAR( OGR_G_GetX( geometry, 0 ), 210.0, 1e-9 );
  QGSCOMPARENEAR( OGR_G_GetY( geometry, 0 ), -130.0, 1e-9 );
  OGR_F_Destroy( feature );
  GDALClose( ds );
}

void TestProjectToImage::rawImageSitsInPixelSpace()
{
  // docs/conventions.md §1: QGIS places a raster without georeferencing at x = col,
  // y = -row, so image-space layers overlay it exactly.
  const QString path = mDir.filePath( QStringLiteral( "pattern.tif" ) );
  GDALDatasetH ds = GDALCreate( GDALGetDriverByName( "GTiff" ), path.toUtf8().constData(), 40, 30, 1, GDT_Byte, nullptr );
  QVERIFY( ds );
  std::vector<unsigned char> pixels( 40 * 30 );
  for ( int row = 0; row < 30; ++row )
    for ( int col = 0; col < 40; ++col )
      pixels[row * 40 + col] = static_cast<unsigned char>( col + 100 * ( row % 2 ) );
  QCOMPARE( GDALRasterIO( GDALGetRasterBand( ds, 1 ), GF_Write, 0, 0, 40, 30, pixels.data(), 40, 30, GDT_Byte, 0, 0 ), CE_None );
  GDALClose( ds );

  QgsRasterLayer raster( path, QStringLiteral( "pattern" ) );
  QVERIFY( raster.isValid() );
  QCOMPARE( raster.extent(), QgsRectangle( 0, -30, 40, 0 ) );
  bool ok = false;
  // centre of pixel (col 7, row 3) is (7.5, 3.5): x = 7.5, y = -3.5
  QCOMPARE( raster.dataProvider()->sample( QgsPointXY( 7.5, -3.5 ), 1, &ok ), 107.0 );
  QVERIFY( ok );
  QCOMPARE( raster.dataProvider()->sample( QgsPointXY( 39.5, -28.5 ), 1, &ok ), 39.0 );
}

void TestProjectToImage::badInputFailsWithOneSentenceAndNoOutput_data()
{
  QTest::addColumn<QString>( "block" );
  QTest::addColumn<QString>( "image" );
  QTest::addColumn<QString>( "layerType" );
  QTest::addColumn<QString>( "expected" );

  const QString good = QString::fromLatin1( kBlockTemplate ).arg( QStringLiteral( "EPSG:32617" ) );
  QTest::newRow( "malformed json" ) << QStringLiteral( "{\"format\": \"geostation-block\", " ) << "N1" << "PointZ" << "not valid JSON";
  QTest::newRow( "geographic crs" ) << QString::fromLatin1( kBlockTemplate ).arg( QStringLiteral( "EPSG:4326" ) ) << "N1" << "PointZ" << "at $.crs: 'EPSG:4326' (WGS 84) is a geographic CRS";
  QTest::newRow( "unknown camera" ) << QString( good ).replace( "\"camera\": \"nadir\", \"station\": \"S1\", \"path\": \"images/N2.tif\"", "\"camera\": \"rear\", \"station\": \"S1\", \"path\": \"images/N2.tif\"" )
                                    << "N1" << "PointZ" << "at $.images[1].camera: camera \"rear\" is not defined";
  QTest::newRow( "unknown image" ) << good << "N7" << "PointZ" << "image \"N7\" is not in the block";
  QTest::newRow( "not oriented" ) << good << "N2" << "PointZ" << "has no exterior orientation";
  QTest::newRow( "missing image file" ) << QString( good ).replace( "images/N1.tif", "images/gone.tif" ) << "N1" << "PointZ" << "does not exist";
  QTest::newRow( "no heights" ) << good << "N1" << "Point" << "no Z values";
}

void TestProjectToImage::badInputFailsWithOneSentenceAndNoOutput()
{
  QFETCH( QString, block );
  QFETCH( QString, image );
  QFETCH( QString, layerType );
  QFETCH( QString, expected );

  const QString blockPath = writeBlock( QStringLiteral( "bad.geostation.json" ), block );
  QgsVectorLayer *layer = pointLayer( layerType, QStringLiteral( "EPSG:32617" ), { { layerType == "Point" ? "Point (500010 4400020)" : "PointZ (500010 4400020 100)", "pole" } } );
  const QString outputPath = mDir.filePath( QStringLiteral( "must-not-exist.gpkg" ) );
  bool ok = true;
  RecordingFeedback feedback;
  run( { { "BLOCK", blockPath }, { "IMAGE", image }, { "INPUT", layer->id() }, { "OUTPUT", outputPath } }, &ok, &feedback );
  QVERIFY( !ok );
  QCOMPARE( feedback.errors.size(), 1 );
  QVERIFY2( feedback.errors.first().contains( expected ), qPrintable( feedback.errors.first() ) );
  QVERIFY2( !QFile::exists( outputPath ), "a failed run left an output file" );
}

int main( int argc, char **argv )
{
  return runQgisTests<TestProjectToImage>( argc, argv );
}

#include "testprojecttoimage.moc"

// geostation:monoplot on an oblique photo over synthetic terrain.
#include <QTemporaryDir>
#include <QtTest/QtTest>

#include <Eigen/Geometry>
#include <gdal.h>
#include <gdal_utils.h>
#include <ogr_api.h>
#include <ogr_srs_api.h>

#include <qgsapplication.h>
#include <qgsprocessingalgorithm.h>
#include <qgsprocessingcontext.h>
#include <qgsprocessingregistry.h>
#include <qgsprocessingutils.h>
#include <qgsproject.h>
#include <qgstest.h>
#include <qgslinestring.h>
#include <qgsmultilinestring.h>
#include <qgspolygon.h>
#include <qgsvectorlayer.h>

#include "dem/monoplotter.h"
#include "geometry/projection.h"
#include "geometry/rotation.h"
#include "geostationprovider.h"
#include "io/block.h"
#include "io/pixelspacegpkg.h"
#include "processingtestutils.h"
#include "syntheticterrain.h"

namespace
{
  using syntheticterrain::kX0;
  using syntheticterrain::kY0;
  double terrain( double x, double y ) { return syntheticterrain::height( x, y ); }
} // namespace

class TestMonoplotAlgorithm : public QObject
{
    Q_OBJECT

  private slots:
    void initTestCase();
    void monoplotsPointsAndDrapesLines();
    void projectToImageDrapesAndTestsOcclusion();
    void projectToImageDensifiesLinesAndPolygons();
    void projectToImageCutsLinesAtTheCameraPlane();
    void projectToImageClipsPolygonsAroundTheCamera();
    void projectToImageKeepsEveryPartOfAMultiLine();
    void badInput_data();
    void badInput();
    void keepsGoingPastFeaturesItCannotResolve();
    void bridgesLargerHolesWhenAsked();
    void cutsALineAtAHoleAndKeepsItsLongestPart();
    void corruptDemStopsWithOneSentenceAndNoFile();

  private:
    QString pixelLayer( const QString &name, const QList<QPair<QString, std::vector<Eigen::Vector2d>>> &features, bool line, const char *crs = nullptr );
    QVariantMap run( const QVariantMap &parameters, bool *ok, RecordingFeedback *feedback );
    //! project_to_image of a layer (added to the project) into P1 (DENSIFY_PX 4, no DEM).
    QVariantMap projectToImage( QgsVectorLayer *layer, bool *ok, RecordingFeedback *feedback );
    //! The OUTPUT layer of an algorithm's result.
    QgsVectorLayer *outputLayer( const QVariantMap &result );
    //! The features of an output file by their `name` (empty if it cannot be read).
    QMap<QString, QgsFeature> featuresByName( const QString &path );
    QTemporaryDir mDir;
    QString mBlock;
    std::unique_ptr<geostation::OrientedImage> mImage;
    QgsProcessingContext mContext;
};

void TestMonoplotAlgorithm::initTestCase()
{
  QVERIFY( registerGeoStationProvider() || QgsApplication::processingRegistry()->providerById( "geostation" ) );
  GDALAllRegister();
  syntheticterrain::writeTerrain( mDir.filePath( "dem.tif" ).toStdString(), 500 );
  syntheticterrain::writeTerrain( mDir.filePath( "dem-nocrs.tif" ).toStdString(), 500, kX0, nullptr );
  syntheticterrain::writeTerrain( mDir.filePath( "dem-elsewhere.tif" ).toStdString(), 500, kX0 + 50000.0 );
  GDALClose( GDALCreate( GDALGetDriverByName( "GTiff" ), mDir.filePath( "photo.tif" ).toUtf8().constData(), 1280, 960, 1, GDT_Byte, nullptr ) );

  // The camera on a 60 m mast, looking north and down (omega-phi-kappa from the look direction).
  const Eigen::Vector3d centre( kX0 + 500.0, kY0 - 950.0, terrain( kX0 + 500.0, kY0 - 950.0 ) + 60.0 );
  const Eigen::Vector3d forward = Eigen::Vector3d( 0.0, 300.0, -120.0 ).normalized();
  const Eigen::Vector3d right = forward.cross( Eigen::Vector3d::UnitZ() ).normalized();
  Eigen::Matrix3d worldFromCamera;
  worldFromCamera << right, right.cross( forward ), -forward;
  const Eigen::Vector3d opk = geostation::omegaPhiKappaDegFromRotation( worldFromCamera );
  const QString block = QStringLiteral( R"json({"format": "geostation-block", "version": 1, "crs": "EPSG:32633",
    "cameras": [{"id": "mast", "width": 1280, "height": 960, "f": 1100.0, "cx": 641.3, "cy": 478.9,
                 "distortion": {"model": "opencv", "k1": -0.2, "k2": 0.05, "p1": 0.0005, "p2": -0.0003}}],
    "images": [{"id": "P1", "camera": "mast", "path": "photo.tif", "X": %1, "Y": %2, "Z": %3, "omega": %4, "phi": %5, "kappa": %6,
                "sigma": {"X": 0.05, "Y": 0.05, "Z": 0.05, "omega": 0.01, "phi": 0.01, "kappa": 0.01}}]})json" )
                        .arg( centre.x(), 0, 'f', 6 ).arg( centre.y(), 0, 'f', 6 ).arg( centre.z(), 0, 'f', 6 )
                        .arg( opk.x(), 0, 'f', 9 ).arg( opk.y(), 0, 'f', 9 ).arg( opk.z(), 0, 'f', 9 );
  QFile file( mDir.filePath( "block.geostation.json" ) );
  QVERIFY( file.open( QIODevice::WriteOnly ) );
  file.write( block.toUtf8() );
  file.close();
  mBlock = file.fileName();
  const geostation::Block loaded = geostation::Block::load( mBlock.toStdString() );
  mImage = std::make_unique<geostation::OrientedImage>( loaded.camera( "mast" ), *loaded.image( "P1" ).exterior );
  mContext.setProject( QgsProject::instance() );
}

QString TestMonoplotAlgorithm::pixelLayer( const QString &name, const QList<QPair<QString, std::vector<Eigen::Vector2d>>> &features, bool line, const char *crs )
{
  const QString path = mDir.filePath( name + ".gpkg" );
  GDALDatasetH ds = GDALCreate( GDALGetDriverByName( "GPKG" ), path.toUtf8().constData(), 0, 0, 0, GDT_Unknown, nullptr );
  OGRSpatialReferenceH srs = nullptr;
  if ( crs )
  {
    srs = OSRNewSpatialReference( nullptr );
    OSRSetFromUserInput( srs, crs );
  }
  OGRLayerH layer = GDALDatasetCreateLayer( ds, "digitised", srs, line ? wkbLineString : wkbPoint, nullptr );
  OGRFieldDefnH field = OGR_Fld_Create( "name", OFTString );
  OGR_L_CreateField( layer, field, TRUE );
  OGR_Fld_Destroy( field );
  for ( const auto &[label, pixels] : features )
  {
    OGRFeatureH f = OGR_F_Create( OGR_L_GetLayerDefn( layer ) );
    OGR_F_SetFieldString( f, 0, label.toUtf8().constData() );
    OGRGeometryH g = OGR_G_CreateGeometry( line ? wkbLineString : wkbPoint );
    for ( const Eigen::Vector2d &p : pixels )
      OGR_G_AddPoint_2D( g, p.x(), -p.y() ); // x = col, y = -row
    OGR_F_SetGeometryDirectly( f, g );
    if ( OGR_L_CreateFeature( layer, f ) != OGRERR_NONE )
      qFatal( "cannot write the test layer" );
    OGR_F_Destroy( f );
  }
  GDALClose( ds );
  if ( srs )
    OSRDestroySpatialReference( srs );
  else
    geostation::markGeoPackageLayerAsPixelSpace( path.toStdString() );
  return path;
}

QVariantMap TestMonoplotAlgorithm::run( const QVariantMap &parameters, bool *ok, RecordingFeedback *feedback )
{
  std::unique_ptr<QgsProcessingAlgorithm> alg( QgsApplication::processingRegistry()->algorithmById( "geostation:monoplot" )->create() );
  return alg->run( parameters, mContext, feedback, ok );
}

void TestMonoplotAlgorithm::monoplotsPointsAndDrapesLines()
{
  // Truth points on the terrain, digitised at their exact pixels.
  QList<QPair<QString, std::vector<Eigen::Vector2d>>> points;
  std::vector<Eigen::Vector3d> truth;
  for ( int i = 0; i < 12; ++i )
  {
    const double x = kX0 + 420.0 + 15.0 * i, y = kY0 - 800.0 + 9.0 * i;
    const Eigen::Vector3d p( x, y, terrain( x, y ) );
    const geostation::GroundProjection g = mImage->projectGroundToPixel( p );
    QVERIFY( g.inFrame );
    points << qMakePair( QStringLiteral( "pt%1" ).arg( i ), std::vector<Eigen::Vector2d> { g.pixelInImage } );
    truth.push_back( p );
  }
  bool ok = false;
  RecordingFeedback feedback;
  QVariantMap result = run( { { "BLOCK", mBlock }, { "IMAGE", "P1" }, { "DEM", mDir.filePath( "dem.tif" ) }, { "INPUT", pixelLayer( "points", points, false ) },
    { "OUTPUT", QgsProcessing::TEMPORARY_OUTPUT } }, &ok, &feedback );
  QVERIFY2( ok, qPrintable( feedback.errors.join( '\n' ) ) );
  QgsVectorLayer *out = outputLayer( result );
  QVERIFY( out );
  QCOMPARE( out->crs().authid(), QStringLiteral( "EPSG:32633" ) );
  QVERIFY( QgsWkbTypes::hasZ( out->wkbType() ) );
  QgsFeature f;
  QgsFeatureIterator it = out->getFeatures();
  int n = 0;
  while ( it.nextFeature( f ) )
  {
    const int i = f.attribute( "name" ).toString().mid( 2 ).toInt();
    const QgsPoint p = *f.geometry().vertices_begin();
    // Truth here is the analytic terrain; the DEM's bilinear surface differs by its sampling.
    QGSCOMPARENEAR( p.x(), truth[i].x(), 0.2 );
    QGSCOMPARENEAR( p.y(), truth[i].y(), 0.6 );
    QGSCOMPARENEAR( p.z(), truth[i].z(), 0.1 );
    QVERIFY( f.attribute( "sigma_y" ).toDouble() > f.attribute( "sigma_x" ).toDouble() );
    QCOMPARE( f.attribute( "method" ).toString(), QStringLiteral( "monoplot-DEM" ) );
    QCOMPARE( f.attribute( "n_vertices" ).toInt(), 1 );
    ++n;
  }
  QCOMPARE( n, 12 );

  // A line of 900 px drapes into at least 900 / 5 vertices.
  result = run( { { "BLOCK", mBlock }, { "IMAGE", "P1" }, { "DEM", mDir.filePath( "dem.tif" ) },
    { "INPUT", pixelLayer( "line", { qMakePair( QStringLiteral( "ridge" ), std::vector<Eigen::Vector2d> { { 200.0, 700.0 }, { 1100.0, 650.0 } } ) }, true ) },
    { "DENSIFY_PX", 5.0 }, { "OUTPUT", QgsProcessing::TEMPORARY_OUTPUT } }, &ok, &feedback );
  QVERIFY2( ok, qPrintable( feedback.errors.join( '\n' ) ) );
  out = outputLayer( result );
  QVERIFY( out->getFeatures().nextFeature( f ) );
  QVERIFY( f.attribute( "n_vertices" ).toInt() >= 180 );
  QVERIFY( f.geometry().constGet()->nCoordinates() >= 180 );
}

void TestMonoplotAlgorithm::projectToImageDrapesAndTestsOcclusion()
{
  // 2D map points across the hills: draped on the DEM, some hidden by ridges.
  const geostation::Dem dem( mDir.filePath( "dem.tif" ).toStdString() );
  const geostation::CrsTransform same( "EPSG:32633", "EPSG:32633" );
  const geostation::Monoplotter expected( *mImage, dem, same );
  auto *layer = new QgsVectorLayer( QStringLiteral( "Point?crs=EPSG:32633&field=name:string" ), QStringLiteral( "map points" ), QStringLiteral( "memory" ) );
  QMap<QString, geostation::MapPointInImage> truth;
  int k = 0;
  for ( double y = kY0 - 850.0; y < kY0 - 250.0; y += 40.0 )
    for ( double x = kX0 + 300.0; x < kX0 + 700.0; x += 40.0, ++k )
    {
      QgsFeature f( layer->fields() );
      f.setGeometry( QgsGeometry( new QgsPoint( x, y ) ) );
      f.setAttribute( 0, QStringLiteral( "m%1" ).arg( k ) );
      layer->dataProvider()->addFeature( f );
      truth.insert( QStringLiteral( "m%1" ).arg( k ), expected.groundToImage( { x, y, *dem.heightAt( x, y ) } ) );
    }
  // and one off the DEM's west edge: no height for it, the others go on (issue: batches keep going)
  QgsFeature offDem( layer->fields() );
  offDem.setGeometry( QgsGeometry( new QgsPoint( kX0 - 50.0, kY0 - 500.0 ) ) );
  offDem.setAttribute( 0, QStringLiteral( "off the DEM" ) );
  layer->dataProvider()->addFeature( offDem );
  QgsProject::instance()->addMapLayer( layer );
  bool ok = false;
  RecordingFeedback feedback;
  std::unique_ptr<QgsProcessingAlgorithm> alg( QgsApplication::processingRegistry()->algorithmById( "geostation:project_to_image" )->create() );
  const QVariantMap result = alg->run( { { "BLOCK", mBlock }, { "IMAGE", "P1" }, { "INPUT", layer->id() }, { "DEM", mDir.filePath( "dem.tif" ) },
    { "OUTPUT", QgsProcessing::TEMPORARY_OUTPUT } }, mContext, &feedback, &ok );
  QVERIFY2( ok, qPrintable( feedback.errors.join( '\n' ) ) );
  QgsVectorLayer *out = outputLayer( result );
  QVERIFY( out );
  int visible = 0, hidden = 0;
  QgsFeature f;
  QgsFeatureIterator it = out->getFeatures();
  while ( it.nextFeature( f ) )
  {
    if ( f.attribute( "name" ).toString() == QLatin1String( "off the DEM" ) )
    {
      QCOMPARE( f.attribute( "status" ).toString(), QStringLiteral( "outside_dem" ) );
      QVERIFY( f.attribute( "message" ).toString().contains( "outside the DEM" ) );
      QVERIFY( !f.hasGeometry() );
      continue;
    }
    const geostation::MapPointInImage &t = truth[f.attribute( "name" ).toString()];
    QVERIFY( f.attribute( "status" ).toString() != QLatin1String( "outside_dem" ) );
    QCOMPARE( f.attribute( "in_frame" ).toBool(), t.projection.inFrame );
    QCOMPARE( f.attribute( "visible" ).toBool(), t.visible );
    if ( t.projection.ok() )
      QGSCOMPARENEAR( f.attribute( "col" ).toDouble(), t.projection.pixelInImage.x(), 1e-6 );
    if ( t.projection.inFrame )
      ( t.visible ? visible : hidden ) += 1;
  }
  QVERIFY( visible > 10 );
  QVERIFY( hidden > 3 );
  QCOMPARE( result.value( "UNRESOLVED_COUNT" ).toInt(), 1 );
  QCOMPARE( feedback.warnings.filter( "outside the DEM" ).size(), 1 );
}

void TestMonoplotAlgorithm::projectToImageDensifiesLinesAndPolygons()
{
  const geostation::Dem dem( mDir.filePath( "dem.tif" ).toStdString() );
  const geostation::CrsTransform same( "EPSG:32633", "EPSG:32633" );
  const geostation::Monoplotter expected( *mImage, dem, same );

  // A 2D road across the hills, draped on the DEM.
  auto *roads = new QgsVectorLayer( QStringLiteral( "LineString?crs=EPSG:32633&field=name:string" ), QStringLiteral( "roads" ), QStringLiteral( "memory" ) );
  QgsFeature road( roads->fields() );
  road.setGeometry( QgsGeometry::fromWkt( QStringLiteral( "LineString (%1 %2, %3 %4)" ).arg( kX0 + 400.0 ).arg( kY0 - 750.0 ).arg( kX0 + 620.0 ).arg( kY0 - 700.0 ) ) );
  road.setAttribute( 0, QStringLiteral( "ridge road" ) );
  roads->dataProvider()->addFeature( road );
  QgsProject::instance()->addMapLayer( roads );
  bool ok = false;
  RecordingFeedback feedback;
  std::unique_ptr<QgsProcessingAlgorithm> alg( QgsApplication::processingRegistry()->algorithmById( "geostation:project_to_image" )->create() );
  QVariantMap result = alg->run( { { "BLOCK", mBlock }, { "IMAGE", "P1" }, { "INPUT", roads->id() }, { "DEM", mDir.filePath( "dem.tif" ) },
    { "DENSIFY_PX", 4.0 }, { "OUTPUT", QgsProcessing::TEMPORARY_OUTPUT } }, mContext, &feedback, &ok );
  QVERIFY2( ok, qPrintable( feedback.errors.join( '\n' ) ) );
  QgsVectorLayer *out = outputLayer( result );
  QCOMPARE( out->wkbType(), QgsWkbTypes::LineString );
  QgsFeature f;
  QVERIFY( out->getFeatures().nextFeature( f ) );
  const QgsLineString *line = qgsgeometry_cast<const QgsLineString *>( f.geometry().constGet() );
  QVERIFY( line );
  const Eigen::Vector3d a( kX0 + 400.0, kY0 - 750.0, *dem.heightAt( kX0 + 400.0, kY0 - 750.0 ) ), b( kX0 + 620.0, kY0 - 700.0, *dem.heightAt( kX0 + 620.0, kY0 - 700.0 ) );
  const std::vector<geostation::MapPointInImage> curve = expected.groundLineToImage( { a, b }, 4.0, true );
  QCOMPARE( line->numPoints(), static_cast<int>( curve.size() ) );
  QVERIFY( line->numPoints() > 10 );
  for ( int i = 0; i < line->numPoints(); ++i )
  {
    QGSCOMPARENEAR( line->xAt( i ), curve[i].projection.pixelInImage.x(), 1e-6 );
    QGSCOMPARENEAR( line->yAt( i ), -curve[i].projection.pixelInImage.y(), 1e-6 );
    if ( i > 0 )
      QVERIFY( std::hypot( line->xAt( i ) - line->xAt( i - 1 ), line->yAt( i ) - line->yAt( i - 1 ) ) <= 4.0 + 1e-9 );
  }
  QVERIFY( f.attribute( "col" ).isNull() ); // a line has no single pixel

  // A polygon with heights, without DEM: a closed, densified ring.
  auto *parcels = new QgsVectorLayer( QStringLiteral( "PolygonZ?crs=EPSG:32633" ), QStringLiteral( "parcels" ), QStringLiteral( "memory" ) );
  QgsFeature parcel( parcels->fields() );
  parcel.setGeometry( QgsGeometry::fromWkt( QStringLiteral( "PolygonZ ((%1 %2 130, %3 %2 130, %3 %4 130, %1 %4 130, %1 %2 130))" )
                      .arg( kX0 + 450.0 ).arg( kY0 - 760.0 ).arg( kX0 + 560.0 ).arg( kY0 - 690.0 ) ) );
  parcels->dataProvider()->addFeature( parcel );
  QgsProject::instance()->addMapLayer( parcels );
  result = alg->run( { { "BLOCK", mBlock }, { "IMAGE", "P1" }, { "INPUT", parcels->id() }, { "DENSIFY_PX", 3.0 },
    { "OUTPUT", QgsProcessing::TEMPORARY_OUTPUT } }, mContext, &feedback, &ok );
  QVERIFY2( ok, qPrintable( feedback.errors.join( '\n' ) ) );
  out = outputLayer( result );
  QCOMPARE( out->wkbType(), QgsWkbTypes::Polygon );
  QVERIFY( out->getFeatures().nextFeature( f ) );
  const QgsPolygon *polygon = qgsgeometry_cast<const QgsPolygon *>( f.geometry().constGet() );
  QVERIFY( polygon );
  const QgsCurve *ring = polygon->exteriorRing();
  QVERIFY( ring->isClosed() );
  QVERIFY( ring->numPoints() > 5 + 20 );
}

void TestMonoplotAlgorithm::badInput_data()
{
  QTest::addColumn<QString>( "dem" );
  QTest::addColumn<QString>( "crs" );
  QTest::addColumn<double>( "col" );
  QTest::addColumn<QString>( "expected" );
  QTest::newRow( "dem without crs" ) << "dem-nocrs.tif" << QString() << 640.0 << "has no CRS";
  QTest::newRow( "dem elsewhere" ) << "dem-elsewhere.tif" << QString() << 640.0 << "does not cover the footprint";
  QTest::newRow( "input in a map crs" ) << "dem.tif" << "EPSG:4326" << 640.0 << "not in image pixel space";
  QTest::newRow( "outside the frame" ) << "dem.tif" << QString() << 1500.0 << "outside the image frame";
}

void TestMonoplotAlgorithm::badInput()
{
  QFETCH( QString, dem );
  QFETCH( QString, crs );
  QFETCH( double, col );
  QFETCH( QString, expected );
  const QString tag = QString( QTest::currentDataTag() ).replace( ' ', '-' );
  const QString input = pixelLayer( "bad-" + tag, { qMakePair( QStringLiteral( "p" ), std::vector<Eigen::Vector2d> { { col, 700.0 } } ) }, false,
                                    crs.isEmpty() ? nullptr : crs.toUtf8().constData() );
  const QString output = mDir.filePath( "never-" + tag + ".gpkg" );
  bool ok = true;
  RecordingFeedback feedback;
  run( { { "BLOCK", mBlock }, { "IMAGE", "P1" }, { "DEM", mDir.filePath( dem ) }, { "INPUT", input }, { "OUTPUT", output } }, &ok, &feedback );
  QVERIFY( !ok );
  QVERIFY2( feedback.errors.join( ' ' ).contains( expected ), qPrintable( feedback.errors.join( '\n' ) ) );
  QVERIFY( !QFile::exists( output ) );
}

void TestMonoplotAlgorithm::projectToImageCutsLinesAtTheCameraPlane()
{
  // A 3-D line from the ground in view to a point behind the camera: the part in front is kept, cut
  // where the line leaves the projectable field, and counted.
  const Eigen::Vector3d centre = mImage->exterior().projectionCentre, view = mImage->exterior().viewingDirection();
  const Eigen::Vector3d front = mImage->worldRayFromPixel( { 640.5, 700.5 } )->origin + 250.0 * mImage->worldRayFromPixel( { 640.5, 700.5 } )->direction;
  const Eigen::Vector3d behind = centre - 80.0 * view + Eigen::Vector3d( 5.0, 0.0, 0.0 );
  auto *lines = new QgsVectorLayer( QStringLiteral( "LineStringZ?crs=EPSG:32633&field=name:string" ), QStringLiteral( "through" ), QStringLiteral( "memory" ) );
  QgsFeature f( lines->fields() );
  f.setGeometry( QgsGeometry( new QgsLineString( QVector<QgsPoint> { QgsPoint( front.x(), front.y(), front.z() ), QgsPoint( behind.x(), behind.y(), behind.z() ) } ) ) );
  f.setAttribute( 0, QStringLiteral( "through the camera" ) );
  lines->dataProvider()->addFeature( f );
  bool ok = false;
  RecordingFeedback feedback;
  const QVariantMap result = projectToImage( lines, &ok, &feedback );
  QVERIFY2( ok, qPrintable( feedback.errors.join( '\n' ) ) );
  QCOMPARE( result.value( "CLIPPED_COUNT" ).toInt(), 1 );
  QCOMPARE( result.value( "PROJECTED_COUNT" ).toInt(), 1 );
  QVERIFY( feedback.warnings.join( ' ' ).contains( "cut" ) );
  QgsVectorLayer *out = outputLayer( result );
  QgsFeature g;
  QVERIFY( out->getFeatures().nextFeature( g ) );
  const QgsLineString *line = qgsgeometry_cast<const QgsLineString *>( g.geometry().constGet() );
  QVERIFY( line && line->numPoints() >= 2 );
  // it starts at the ground point in view and ends where the line leaves the lens field, outside the frame
  QGSCOMPARENEAR( line->xAt( 0 ), 640.5, 1e-6 );
  QGSCOMPARENEAR( line->yAt( 0 ), -700.5, 1e-6 );
  const QgsPoint end = line->endPoint();
  QVERIFY( end.x() < 0 || end.x() > 1280 || -end.y() < 0 || -end.y() > 960 );
  QCOMPARE( g.attribute( "in_frame" ).toBool(), false );
}

void TestMonoplotAlgorithm::projectToImageClipsPolygonsAroundTheCamera()
{
  // A flat area 20 m below the mast camera, around it on every side: clipped in 3D to what the photo can show.
  const Eigen::Vector3d centre = mImage->exterior().projectionCentre;
  const double z = centre.z() - 20.0;
  auto *areas = new QgsVectorLayer( QStringLiteral( "PolygonZ?crs=EPSG:32633&field=name:string" ), QStringLiteral( "around" ), QStringLiteral( "memory" ) );
  QgsFeature f( areas->fields() );
  QgsPolygon *polygon = new QgsPolygon();
  polygon->setExteriorRing( new QgsLineString( QVector<QgsPoint> { QgsPoint( centre.x() - 300, centre.y() - 100, z ), QgsPoint( centre.x() + 300, centre.y() - 100, z ),
                            QgsPoint( centre.x() + 300, centre.y() + 400, z ), QgsPoint( centre.x() - 300, centre.y() + 400, z ), QgsPoint( centre.x() - 300, centre.y() - 100, z ) } ) );
  f.setGeometry( QgsGeometry( polygon ) );
  f.setAttribute( 0, QStringLiteral( "around the mast" ) );
  areas->dataProvider()->addFeature( f );
  bool ok = false;
  RecordingFeedback feedback;
  const QVariantMap result = projectToImage( areas, &ok, &feedback );
  QVERIFY2( ok, qPrintable( feedback.errors.join( '\n' ) ) );
  QCOMPARE( result.value( "PROJECTED_COUNT" ).toInt(), 1 );
  QCOMPARE( result.value( "CLIPPED_COUNT" ).toInt(), 1 );
  QCOMPARE( result.value( "BEHIND_CAMERA_COUNT" ).toInt(), 0 );
  QgsVectorLayer *out = outputLayer( result );
  QgsFeature g;
  QVERIFY( out->getFeatures().nextFeature( g ) );
  QCOMPARE( g.attribute( "name" ).toString(), QStringLiteral( "around the mast" ) );
  QVERIFY( g.attribute( "depth_m" ).toDouble() > 0 );
  const QgsGeometry image = g.geometry();
  QVERIFY( image.type() == QgsWkbTypes::PolygonGeometry );
  QVERIFY( image.isGeosValid() );
  // the area fills the lower two thirds of the frame (its rays meet the plane within the area) ...
  QVERIFY( image.contains( QgsGeometry::fromRect( QgsRectangle( 0.5, -959.5, 1279.5, -300.5 ) ) ) );
  // ... but not the sky: the top row looks above the horizon
  QVERIFY( !image.contains( QgsGeometry::fromPointXY( QgsPointXY( 640.5, -0.5 ) ) ) );
}

void TestMonoplotAlgorithm::projectToImageKeepsEveryPartOfAMultiLine()
{
  // a kerb line from the left of the view round behind the camera to its right: two parts in the photo
  const Eigen::Vector3d centre = mImage->exterior().projectionCentre, view = mImage->exterior().viewingDirection();
  const auto ground = [&]( const Eigen::Vector2d &pixel ) { return *mImage->worldRayFromPixel( pixel ); };
  const Eigen::Vector3d left = ground( { 100.5, 800.5 } ).origin + 150.0 * ground( { 100.5, 800.5 } ).direction;
  const Eigen::Vector3d right = ground( { 1180.5, 800.5 } ).origin + 150.0 * ground( { 1180.5, 800.5 } ).direction;
  const Eigen::Vector3d behind = centre - 60.0 * view;
  const QVector<QgsPoint> vertices { QgsPoint( left.x(), left.y(), left.z() ), QgsPoint( behind.x(), behind.y(), behind.z() ), QgsPoint( right.x(), right.y(), right.z() ) };
  for ( const bool multi : { false, true } )
  {
    auto *lines = new QgsVectorLayer( multi ? QStringLiteral( "MultiLineStringZ?crs=EPSG:32633" ) : QStringLiteral( "LineStringZ?crs=EPSG:32633" ),
                                      QStringLiteral( "round" ), QStringLiteral( "memory" ) );
    QgsFeature f( lines->fields() );
    if ( multi )
    {
      QgsMultiLineString *m = new QgsMultiLineString();
      m->addGeometry( new QgsLineString( vertices ) );
      f.setGeometry( QgsGeometry( m ) );
    }
    else
      f.setGeometry( QgsGeometry( new QgsLineString( vertices ) ) );
    lines->dataProvider()->addFeature( f );
    bool ok = false;
    RecordingFeedback feedback;
    const QVariantMap result = projectToImage( lines, &ok, &feedback );
    QVERIFY2( ok, qPrintable( feedback.errors.join( '\n' ) ) );
    QCOMPARE( result.value( "CLIPPED_COUNT" ).toInt(), 1 );
    QgsVectorLayer *out = outputLayer( result );
    QgsFeature g;
    QVERIFY( out->getFeatures().nextFeature( g ) );
    const QgsGeometry inImage = g.geometry();
    // the single line keeps one part, the multi-line both; each starts at its ground point in view
    QCOMPARE( inImage.constGet()->partCount(), multi ? 2 : 1 );
    const QgsGeometry start = QgsGeometry::fromPointXY( QgsPointXY( 100.5, -800.5 ) ), end = QgsGeometry::fromPointXY( QgsPointXY( 1180.5, -800.5 ) );
    QVERIFY( inImage.distance( start ) < 1e-6 || inImage.distance( end ) < 1e-6 );
    if ( multi )
      QVERIFY( inImage.distance( start ) < 1e-6 && inImage.distance( end ) < 1e-6 );
  }
}

QVariantMap TestMonoplotAlgorithm::projectToImage( QgsVectorLayer *layer, bool *ok, RecordingFeedback *feedback )
{
  QgsProject::instance()->addMapLayer( layer );
  std::unique_ptr<QgsProcessingAlgorithm> alg( QgsApplication::processingRegistry()->algorithmById( "geostation:project_to_image" )->create() );
  return alg->run( { { "BLOCK", mBlock }, { "IMAGE", "P1" }, { "INPUT", layer->id() }, { "DENSIFY_PX", 4.0 }, { "OUTPUT", QgsProcessing::TEMPORARY_OUTPUT } },
                   mContext, feedback, ok );
}

QgsVectorLayer *TestMonoplotAlgorithm::outputLayer( const QVariantMap &result )
{
  return qobject_cast<QgsVectorLayer *>( QgsProcessingUtils::mapLayerFromString( result.value( "OUTPUT" ).toString(), mContext ) );
}

QMap<QString, QgsFeature> TestMonoplotAlgorithm::featuresByName( const QString &path )
{
  QMap<QString, QgsFeature> byName;
  QgsVectorLayer layer( path, QStringLiteral( "output" ), QStringLiteral( "ogr" ) );
  QgsFeature f;
  QgsFeatureIterator it = layer.getFeatures();
  while ( it.nextFeature( f ) )
    byName[f.attribute( "name" ).toString()] = f;
  return byName;
}

int main( int argc, char **argv )
{
  return runQgisTests<TestMonoplotAlgorithm>( argc, argv );
}

#include "testmonoplotalgorithm.moc"

void TestMonoplotAlgorithm::keepsGoingPastFeaturesItCannotResolve()
{
  // a batch of four: two good points, one outside the frame, one above the horizon (its ray leaves the DEM);
  // the good ones come out, the others with their status and an empty geometry
  const Eigen::Vector3d ground( kX0 + 480.0, kY0 - 780.0, terrain( kX0 + 480.0, kY0 - 780.0 ) );
  const Eigen::Vector2d good = mImage->projectGroundToPixel( ground ).pixelInImage;
  QList<QPair<QString, std::vector<Eigen::Vector2d>>> points { qMakePair( QStringLiteral( "good1" ), std::vector<Eigen::Vector2d> { good } ),
    qMakePair( QStringLiteral( "outside" ), std::vector<Eigen::Vector2d> { { 1500.0, 700.0 } } ),
    qMakePair( QStringLiteral( "sky" ), std::vector<Eigen::Vector2d> { { 640.0, 5.0 } } ),
    qMakePair( QStringLiteral( "good2" ), std::vector<Eigen::Vector2d> { good + Eigen::Vector2d( 30.0, 20.0 ) } ) };
  bool ok = false;
  RecordingFeedback feedback;
  const QString output = mDir.filePath( "mixed-monoplotted.gpkg" );
  const QVariantMap result = run( { { "BLOCK", mBlock }, { "IMAGE", "P1" }, { "DEM", mDir.filePath( "dem.tif" ) }, { "INPUT", pixelLayer( "mixed", points, false ) },
    { "OUTPUT", output } }, &ok, &feedback );
  QVERIFY2( ok, qPrintable( feedback.errors.join( '\n' ) ) );
  QCOMPARE( result.value( "MONOPLOTTED_COUNT" ).toInt(), 2 );
  QCOMPARE( result.value( "FAILED_COUNT" ).toInt(), 2 );
  QMap<QString, QgsFeature> byName = featuresByName( output );
  QCOMPARE( byName.size(), 4 );
  for ( const QString &name : { QStringLiteral( "good1" ), QStringLiteral( "good2" ) } )
  {
    QCOMPARE( byName[name].attribute( "status" ).toString(), QStringLiteral( "ok" ) );
    QVERIFY( byName[name].hasGeometry() );
    QVERIFY( byName[name].attribute( "message" ).isNull() );
  }
  const QgsPoint p = *byName["good1"].geometry().vertices_begin();
  QGSCOMPARENEAR( p.x(), ground.x(), 0.3 );
  QGSCOMPARENEAR( p.y(), ground.y(), 0.8 );
  QCOMPARE( byName["outside"].attribute( "status" ).toString(), QStringLiteral( "outside_image" ) );
  QCOMPARE( byName["sky"].attribute( "status" ).toString(), QStringLiteral( "misses_dem" ) );
  for ( const QString &name : { QStringLiteral( "outside" ), QStringLiteral( "sky" ) } )
  {
    QVERIFY( !byName[name].hasGeometry() || byName[name].geometry().isEmpty() );
    QVERIFY( byName[name].attribute( "sigma_z" ).isNull() );
    QVERIFY( byName[name].attribute( "message" ).toString().contains( "cannot be monoplotted" ) );
  }
  // a warning per failed feature and the counts in the log, not an error
  QVERIFY( feedback.errors.isEmpty() );
  QCOMPARE( feedback.warnings.size(), 2 );
  QVERIFY2( feedback.infos.join( ' ' ).contains( "2 of 4 features monoplotted" ), qPrintable( feedback.infos.join( '\n' ) ) );

  // all of them failing: one sentence, no file
  const QString never = mDir.filePath( "never-all-failing.gpkg" );
  RecordingFeedback failing;
  run( { { "BLOCK", mBlock }, { "IMAGE", "P1" }, { "DEM", mDir.filePath( "dem.tif" ) },
    { "INPUT", pixelLayer( "all-failing", { points[1], points[2] }, false ) }, { "OUTPUT", never } }, &ok, &failing );
  QVERIFY( !ok );
  QVERIFY2( failing.errors.join( ' ' ).contains( "None of the 2 features" ), qPrintable( failing.errors.join( '\n' ) ) );
  QVERIFY( !QFile::exists( never ) );
}

void TestMonoplotAlgorithm::bridgesLargerHolesWhenAsked()
{
  // a nodata hole of 50 x 50 cells (100 m) around a digitised point: too large to fill; bridged when asked,
  // with the bridge's height sigma in the point's precision
  const Eigen::Vector3d ground( kX0 + 480.0, kY0 - 780.0, terrain( kX0 + 480.0, kY0 - 780.0 ) );
  const QString dem = mDir.filePath( "dem-hole.tif" );
  syntheticterrain::writeTerrain( dem.toStdString(), 500, kX0, "EPSG:32633", 0.05, []( int c, int r ) { return c >= 215 && c < 265 && r >= 365 && r < 415; } );
  const Eigen::Vector2d pixel = mImage->projectGroundToPixel( ground ).pixelInImage;
  const QString input = pixelLayer( "in-hole", { qMakePair( QStringLiteral( "hole" ), std::vector<Eigen::Vector2d> { pixel } ),
                                                 qMakePair( QStringLiteral( "good" ), std::vector<Eigen::Vector2d> { { 640.0, 900.0 } } ) }, false );
  bool ok = false;
  RecordingFeedback plain;
  QVariantMap result = run( { { "BLOCK", mBlock }, { "IMAGE", "P1" }, { "DEM", dem }, { "INPUT", input }, { "OUTPUT", mDir.filePath( "hole-plain.gpkg" ) } }, &ok, &plain );
  QVERIFY2( ok, qPrintable( plain.errors.join( '\n' ) ) );
  QCOMPARE( result.value( "FAILED_COUNT" ).toInt(), 1 );
  QVERIFY2( plain.warnings.join( ' ' ).contains( "can be bridged" ), qPrintable( plain.warnings.join( '\n' ) ) );

  RecordingFeedback bridged;
  const QString output = mDir.filePath( "hole-bridged.gpkg" );
  result = run( { { "BLOCK", mBlock }, { "IMAGE", "P1" }, { "DEM", dem }, { "INPUT", input }, { "BRIDGE_HOLES", 60 }, { "OUTPUT", output } }, &ok, &bridged );
  QVERIFY2( ok, qPrintable( bridged.errors.join( '\n' ) ) );
  QCOMPARE( result.value( "FAILED_COUNT" ).toInt(), 0 );
  QCOMPARE( result.value( "BRIDGED_VERTICES" ).toInt(), 1 );
  QVERIFY( result.value( "BRIDGED_DEM_CELLS" ).toInt() > 0 ); // (in the tiles the rays read)
  QVERIFY2( bridged.infos.join( ' ' ).contains( "1 vertices lie on them" ), qPrintable( bridged.infos.join( '\n' ) ) );
  QMap<QString, QgsFeature> byName = featuresByName( output );
  QCOMPARE( byName["hole"].attribute( "status" ).toString(), QStringLiteral( "ok" ) );
  QCOMPARE( byName["hole"].attribute( "n_bridged" ).toInt(), 1 );
  QCOMPARE( byName["good"].attribute( "n_bridged" ).toInt(), 0 );
  // the bridged point is where the terrain is, to within its sigmas; those are larger than the good point's
  const QgsPoint p = *byName["hole"].geometry().vertices_begin();
  const double sigmaY = byName["hole"].attribute( "sigma_y" ).toDouble(), sigmaZ = byName["hole"].attribute( "sigma_z" ).toDouble();
  QVERIFY2( std::abs( p.y() - ground.y() ) <= 3.0 * sigmaY + 0.5, qPrintable( QStringLiteral( "%1 vs %2, sigma %3" ).arg( p.y() ).arg( ground.y() ).arg( sigmaY ) ) );
  QVERIFY2( std::abs( p.z() - ground.z() ) <= 3.0 * sigmaZ + 0.2, qPrintable( QStringLiteral( "%1 vs %2, sigma %3" ).arg( p.z() ).arg( ground.z() ).arg( sigmaZ ) ) );
  QVERIFY( sigmaZ > byName["good"].attribute( "sigma_z" ).toDouble() );
}

void TestMonoplotAlgorithm::corruptDemStopsWithOneSentenceAndNoFile()
{
  // the DEM as tiles of 64 x 64 cells, then the data of every tile overwritten: the file opens, no tile reads.
  // Core reports that as std::runtime_error, which QGIS does not catch (it would end QGIS): the algorithm must
  // turn it into its own error
  const QString tiled = mDir.filePath( "dem-tiled.tif" );
  const char *options[] = { "-co", "TILED=YES", "-co", "BLOCKXSIZE=64", "-co", "BLOCKYSIZE=64", "-co", "COMPRESS=DEFLATE", nullptr };
  GDALTranslateOptions *translate = GDALTranslateOptionsNew( const_cast<char **>( options ), nullptr );
  GDALDatasetH source = GDALOpen( mDir.filePath( "dem.tif" ).toUtf8().constData(), GA_ReadOnly );
  GDALClose( GDALTranslate( tiled.toUtf8().constData(), source, translate, nullptr ) );
  GDALClose( source );
  GDALTranslateOptionsFree( translate );
  std::vector<std::pair<qint64, qint64>> tiles; // offset, size
  GDALDatasetH ds = GDALOpen( tiled.toUtf8().constData(), GA_ReadOnly );
  QVERIFY( ds );
  GDALRasterBandH band = GDALGetRasterBand( ds, 1 );
  for ( int ty = 0; ty * 64 < GDALGetRasterYSize( ds ); ++ty )
    for ( int tx = 0; tx * 64 < GDALGetRasterXSize( ds ); ++tx )
    {
      const char *offset = GDALGetMetadataItem( band, QStringLiteral( "BLOCK_OFFSET_%1_%2" ).arg( tx ).arg( ty ).toUtf8().constData(), "TIFF" );
      const char *size = GDALGetMetadataItem( band, QStringLiteral( "BLOCK_SIZE_%1_%2" ).arg( tx ).arg( ty ).toUtf8().constData(), "TIFF" );
      QVERIFY( offset && size );
      tiles.emplace_back( QByteArray( offset ).toLongLong(), QByteArray( size ).toLongLong() );
    }
  GDALClose( ds );
  QFile file( tiled );
  QVERIFY( file.open( QIODevice::ReadWrite ) );
  for ( const auto &[offset, size] : tiles )
  {
    QVERIFY( file.seek( offset ) );
    file.write( QByteArray( static_cast<int>( size ), '\x5a' ) );
  }
  file.close();

  const QString input = pixelLayer( "on-corrupt", { qMakePair( QStringLiteral( "p" ), std::vector<Eigen::Vector2d> { { 640.0, 900.0 } } ) }, false );
  const QString output = mDir.filePath( "never-corrupt.gpkg" );
  bool ok = true;
  RecordingFeedback feedback;
  run( { { "BLOCK", mBlock }, { "IMAGE", "P1" }, { "DEM", tiled }, { "INPUT", input }, { "OUTPUT", output } }, &ok, &feedback );
  QVERIFY( !ok );
  QCOMPARE( feedback.errors.size(), 1 );
  QVERIFY2( feedback.errors.at( 0 ).contains( "Monoplot image features onto a DEM stopped: reading the DEM failed" ), qPrintable( feedback.errors.at( 0 ) ) );
  QVERIFY( !QFile::exists( output ) );
}

void TestMonoplotAlgorithm::cutsALineAtAHoleAndKeepsItsLongestPart()
{
  // a line across the 100 m nodata hole along the view, 50 m of it before the hole and 30 m beyond: the near part
  // (the longer, with the filled rim) is kept, with the status saying why the line was cut
  const QString dem = mDir.filePath( "dem-hole.tif" );
  if ( !QFile::exists( dem ) )
    syntheticterrain::writeTerrain( dem.toStdString(), 500, kX0, "EPSG:32633", 0.05, []( int c, int r ) { return c >= 215 && c < 265 && r >= 365 && r < 415; } );
  const double x = kX0 + 480.0, nearY = kY0 - 880.0, farY = kY0 - 700.0, holeSouth = kY0 - 830.0;
  const Eigen::Vector3d from( x, nearY, terrain( x, nearY ) ), to( x, farY, terrain( x, farY ) );
  const Eigen::Vector2d a = mImage->projectGroundToPixel( from ).pixelInImage, b = mImage->projectGroundToPixel( to ).pixelInImage;
  bool ok = false;
  RecordingFeedback feedback;
  const QString output = mDir.filePath( "hole-cut.gpkg" );
  const QVariantMap result = run( { { "BLOCK", mBlock }, { "IMAGE", "P1" }, { "DEM", dem }, { "INPUT", pixelLayer( "across-hole", { qMakePair( QStringLiteral( "across" ), std::vector<Eigen::Vector2d> { a, b } ) }, true ) },
    { "OUTPUT", output } }, &ok, &feedback );
  QVERIFY2( ok, qPrintable( feedback.errors.join( '\n' ) ) );
  QCOMPARE( result.value( "MONOPLOTTED_COUNT" ).toInt(), 1 );
  QCOMPARE( result.value( "CUT_COUNT" ).toInt(), 1 );
  QCOMPARE( result.value( "FAILED_COUNT" ).toInt(), 0 );
  const QgsFeature f = featuresByName( output ).value( "across" );
  QCOMPARE( f.attribute( "status" ).toString(), QStringLiteral( "dem_hole" ) );
  QVERIFY2( f.attribute( "message" ).toString().contains( "longest resolved part is kept" ), qPrintable( f.attribute( "message" ).toString() ) );
  QVERIFY( !f.attribute( "sigma_z" ).isNull() );
  const QgsGeometry g = f.geometry();
  QVERIFY( !g.isEmpty() );
  // it starts where the line starts, and ends where the fill of the hole's rim stops (DemOptions::holeFillHalo,
  // 16 cells of 2 m: up to 32 m into the hole)
  const QgsPoint first = *g.vertices_begin();
  QGSCOMPARENEAR( first.x(), x, 1.0 );
  QGSCOMPARENEAR( first.y(), nearY, 1.0 );
  QGSCOMPARENEAR( first.z(), from.z(), 0.5 );
  double maxY = -1e300;
  for ( auto v = g.vertices_begin(); v != g.vertices_end(); ++v )
    maxY = std::max( maxY, ( *v ).y() );
  QVERIFY2( maxY > holeSouth - 6.0 && maxY < holeSouth + 38.0, qPrintable( QStringLiteral( "the kept part ends %1 m from the hole's rim" ).arg( maxY - holeSouth ) ) );
  QVERIFY2( g.length() > 44.0 && g.length() < 90.0, qPrintable( QStringLiteral( "%1 m kept" ).arg( g.length() ) ) );
  QCOMPARE( feedback.warnings.size(), 1 );
}

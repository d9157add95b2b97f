// geostation:intersect and geostation:resection called through the registry,
// with CSV tables (text fields) as users pass them.
#include <QJsonArray>
#include <QJsonDocument>
#include <QJsonObject>
#include <QTemporaryDir>
#include <QtTest/QtTest>

#include <gdal.h>

#include <qgsapplication.h>
#include <qgsprocessingalgorithm.h>
#include <qgsprocessingcontext.h>
#include <qgsprocessingfeedback.h>
#include <qgsprocessingregistry.h>
#include <qgsprocessingutils.h>
#include <qgsproject.h>
#include <qgstest.h>
#include <qgsvectorlayer.h>

#include "geometry/projection.h"
#include "geostationprovider.h"
#include "processingtestutils.h"
#include "io/block.h"

namespace
{
  // Three aerial images, 1000 x 800, f = 1000 px, 1000 m above ground; the
  // third (C) has no exterior orientation in the block: its truth is kept aside.
  const char *kBlock = R"json({
    "format": "geostation-block", "version": 1, "crs": "EPSG:32617",
    "cameras": [{"id": "aerial", "width": 1000, "height": 800, "f": 1000.0, "cx": 500.0, "cy": 400.0,
                 "pixel_size_mm": 0.012, "distortion": {"model": "opencv", "k1": -0.05, "k2": 0.01}}],
    "images": [
      {"id": "A", "camera": "aerial", "path": "images/A.tif", "X": 500000.0, "Y": 4400000.0, "Z": 1100.0, "omega": 0.5, "phi": -0.3, "kappa": 1.0},
      {"id": "B", "camera": "aerial", "path": "images/B.tif", "X": 500300.0, "Y": 4400010.0, "Z": 1102.0, "omega": -0.4, "phi": 0.6, "kappa": 0.5},
      {"id": "C", "camera": "aerial", "path": "images/C.tif"}
    ]})json";
} // namespace

class TestAdjustmentAlgorithms : public QObject
{
    Q_OBJECT

  private slots:
    void initTestCase();
    void intersectRecoversPointsAndCarriesAttributes();
    void intersectBadInput_data();
    void intersectBadInput();
    void resectionOrientsTheImageAndReports();
    void resectionWithFreeInteriorGivesTheImageItsOwnCamera();
    void resectionNamesABlunder();
    void resectionBadInput_data();
    void resectionBadInput();
    void bundleAdjustRecoversThePerturbedBlock();
    void bundleAdjustBadInput_data();
    void bundleAdjustBadInput();

  private:
    QString write( const QString &name, const QString &text );
    QVariantMap run( const QString &algorithm, const QVariantMap &parameters, bool *ok, RecordingFeedback *feedback );
    geostation::OrientedImage truthC() const;
    QString groundCsv( int controlCount, int checkCount );
    QString observationCsv( const QStringList &images, int pointCount, const QMap<QString, QPointF> &offsets = {} );

    QTemporaryDir mDir;
    QString mBlockPath;
    geostation::Block mBlock;
    std::vector<Eigen::Vector3d> mPoints;
    QgsProcessingContext mContext;
};

void TestAdjustmentAlgorithms::initTestCase()
{
  QVERIFY( registerGeoStationProvider() || QgsApplication::processingRegistry()->providerById( "geostation" ) );
  mBlockPath = write( QStringLiteral( "block.geostation.json" ), QString::fromLatin1( kBlock ) );
  QDir( mDir.path() ).mkpath( QStringLiteral( "images" ) );
  GDALAllRegister();
  for ( const char *name : { "A", "B", "C" } )
    GDALClose( GDALCreate( GDALGetDriverByName( "GTiff" ), mDir.filePath( QStringLiteral( "images/%1.tif" ).arg( name ) ).toUtf8().constData(), 1000, 800, 1, GDT_Byte, nullptr ) );
  mBlock = geostation::Block::load( mBlockPath.toStdString() );
  // Points over the overlap of A, B and C, at varied heights (roofs, poles, ground).
  for ( int i = 0; i < 16; ++i )
    mPoints.emplace_back( 500150.0 + 40.0 * ( i % 4 ) - 60.0, 4400000.0 + 45.0 * ( i / 4 ) - 70.0, 100.0 + 30.0 * ( ( i * 7 ) % 5 ) );
  mContext.setProject( QgsProject::instance() );
}

QString TestAdjustmentAlgorithms::write( const QString &name, const QString &text )
{
  QFile file( mDir.filePath( name ) );
  file.open( QIODevice::WriteOnly );
  file.write( text.toUtf8() );
  return file.fileName();
}

geostation::OrientedImage TestAdjustmentAlgorithms::truthC() const
{
  geostation::ExteriorOrientation eo;
  eo.projectionCentre = { 500150.0, 4400150.0, 1098.0 };
  eo.omegaDeg = 1.2;
  eo.phiDeg = -0.8;
  eo.kappaDeg = 92.0;
  return geostation::OrientedImage( mBlock.camera( "aerial" ), eo );
}

QString TestAdjustmentAlgorithms::groundCsv( int controlCount, int checkCount )
{
  QString csv = QStringLiteral( "point_id,X,Y,Z,role\n" );
  for ( int i = 0; i < controlCount + checkCount; ++i )
    csv += QStringLiteral( "P%1,%2,%3,%4,%5\n" ).arg( i ).arg( mPoints[i].x(), 0, 'f', 4 ).arg( mPoints[i].y(), 0, 'f', 4 ).arg( mPoints[i].z(), 0, 'f', 4 )
           .arg( i < controlCount ? "control" : "check" );
  return csv;
}

QString TestAdjustmentAlgorithms::observationCsv( const QStringList &images, int pointCount, const QMap<QString, QPointF> &offsets )
{
  QString csv = QStringLiteral( "point_id,image_id,col,row,class\n" );
  for ( int i = 0; i < pointCount; ++i )
    for ( const QString &imageId : images )
    {
      const geostation::OrientedImage image = imageId == "C" ? truthC() : geostation::OrientedImage( mBlock.camera( "aerial" ), *mBlock.image( imageId.toStdString() ).exterior );
      Eigen::Vector2d pixel = image.projectGroundToPixel( mPoints[i] ).pixelInImage;
      const QPointF offset = offsets.value( QStringLiteral( "P%1@%2" ).arg( i ).arg( imageId ) );
      pixel += Eigen::Vector2d( offset.x(), offset.y() );
      csv += QStringLiteral( "P%1,%2,%3,%4,%5\n" ).arg( i ).arg( imageId ).arg( pixel.x(), 0, 'f', 9 ).arg( pixel.y(), 0, 'f', 9 ).arg( i % 2 ? "pole" : "manhole" );
    }
  return csv;
}

QVariantMap TestAdjustmentAlgorithms::run( const QString &algorithm, const QVariantMap &parameters, bool *ok, RecordingFeedback *feedback )
{
  std::unique_ptr<QgsProcessingAlgorithm> alg( QgsApplication::processingRegistry()->algorithmById( "geostation:" + algorithm )->create() );
  return alg->run( parameters, mContext, feedback, ok );
}

void TestAdjustmentAlgorithms::intersectRecoversPointsAndCarriesAttributes()
{
  QString csv = observationCsv( { "A", "B" }, 12 );
  csv += QStringLiteral( "lonely,A,300.0,300.0,pole\n" ); // seen once: skipped
  const QString observations = write( QStringLiteral( "obs.csv" ), csv );
  bool ok = false;
  RecordingFeedback feedback;
  const QVariantMap result = run( "intersect", { { "BLOCK", mBlockPath }, { "OBSERVATIONS", observations }, { "OUTPUT", QgsProcessing::TEMPORARY_OUTPUT } }, &ok, &feedback );
  QVERIFY2( ok, qPrintable( feedback.errors.join( '\n' ) ) );
  QCOMPARE( result.value( "POINT_COUNT" ).toInt(), 12 );
  QCOMPARE( result.value( "SKIPPED_COUNT" ).toInt(), 1 );
  QVERIFY( feedback.warnings.join( ' ' ).contains( "lonely" ) );

  QgsVectorLayer *out = qobject_cast<QgsVectorLayer *>( QgsProcessingUtils::mapLayerFromString( result.value( "OUTPUT" ).toString(), mContext ) );
  QVERIFY( out );
  QCOMPARE( out->wkbType(), QgsWkbTypes::PointZ );
  QCOMPARE( out->crs().authid(), QStringLiteral( "EPSG:32617" ) );
  QgsFeature f;
  QgsFeatureIterator it = out->getFeatures();
  int count = 0;
  int kept = 0;
  while ( it.nextFeature( f ) )
  {
    if ( f.attribute( "point_id" ).toString() == QLatin1String( "lonely" ) )
    {
      // seen once: kept with its status and an empty geometry, not dropped
      QCOMPARE( f.attribute( "status" ).toString(), QStringLiteral( "too_few_rays" ) );
      QVERIFY( !f.hasGeometry() || f.geometry().isEmpty() );
      QVERIFY( !f.attribute( "message" ).toString().isEmpty() );
      ++kept;
      continue;
    }
    QCOMPARE( f.attribute( "status" ).toString(), QStringLiteral( "ok" ) );
    const int i = f.attribute( "point_id" ).toString().mid( 1 ).toInt();
    const QgsPoint p = *f.geometry().vertices_begin();
    QGSCOMPARENEAR( p.x(), mPoints[i].x(), 1e-5 );
    QGSCOMPARENEAR( p.y(), mPoints[i].y(), 1e-5 );
    QGSCOMPARENEAR( p.z(), mPoints[i].z(), 1e-5 );
    QCOMPARE( f.attribute( "n_images" ).toInt(), 2 );
    QCOMPARE( f.attribute( "class" ).toString(), QString( i % 2 ? "pole" : "manhole" ) );
    QVERIFY( f.attribute( "sigma_z" ).toDouble() > f.attribute( "sigma_x" ).toDouble() ); // aerial: height is weakest
    QVERIFY( f.attribute( "ray_angle_deg" ).toDouble() > 10.0 );
    QVERIFY( !f.attribute( "gross_error" ).toBool() );
    ++count;
  }
  QCOMPARE( count, 12 );
  QCOMPARE( kept, 1 );
}

void TestAdjustmentAlgorithms::intersectBadInput_data()
{
  QTest::addColumn<QString>( "csv" );
  QTest::addColumn<QString>( "expected" );
  QTest::newRow( "unknown image" ) << "point_id,image_id,col,row\nP1,A,10,10\nP1,Z9,12,10\n" << "image \"Z9\" is not in the block";
  QTest::newRow( "not oriented" ) << "point_id,image_id,col,row\nP1,A,10,10\nP1,C,12,10\n" << "has no exterior orientation";
  QTest::newRow( "missing field" ) << "point_id,image_id,x,y\nP1,A,10,10\n" << "no field \"col\"";
  QTest::newRow( "not a number" ) << "point_id,image_id,col,row\nP1,A,10,10\nP1,B,abc,10\n" << "Row 2 of the observations table: \"col\" is \"abc\"";
  QTest::newRow( "no point seen twice" ) << "point_id,image_id,col,row\nP1,A,10,10\nP2,B,12,10\n" << "No point could be intersected";
  QTest::newRow( "empty" ) << "point_id,image_id,col,row\n" << "empty";
}

void TestAdjustmentAlgorithms::intersectBadInput()
{
  QFETCH( QString, csv );
  QFETCH( QString, expected );
  // A file per row: the processing context caches layers by path.
  const QString observations = write( QStringLiteral( "bad-obs-%1.csv" ).arg( QString( QTest::currentDataTag() ).replace( ' ', '-' ) ), csv );
  const QString output = mDir.filePath( QStringLiteral( "must-not-exist.gpkg" ) );
  bool ok = true;
  RecordingFeedback feedback;
  run( "intersect", { { "BLOCK", mBlockPath }, { "OBSERVATIONS", observations }, { "OUTPUT", output } }, &ok, &feedback );
  QVERIFY( !ok );
  QVERIFY2( feedback.errors.join( ' ' ).contains( expected ), qPrintable( feedback.errors.join( '\n' ) ) );
  QVERIFY( !QFile::exists( output ) );
}

void TestAdjustmentAlgorithms::resectionOrientsTheImageAndReports()
{
  const QString gcps = write( QStringLiteral( "gcps.csv" ), groundCsv( 9, 3 ) );
  const QString observations = write( QStringLiteral( "obs-c.csv" ), observationCsv( { "A", "C" }, 12 ) );
  QDir( mDir.path() ).mkpath( QStringLiteral( "out" ) );
  const QString outBlock = mDir.filePath( QStringLiteral( "out/oriented.geostation.json" ) );
  const QString report = mDir.filePath( QStringLiteral( "out/report.json" ) );
  bool ok = false;
  RecordingFeedback feedback;
  const QVariantMap result = run( "resection", { { "BLOCK", mBlockPath }, { "IMAGE", "C" }, { "GCPS", gcps }, { "OBSERVATIONS", observations },
    { "OUTPUT_BLOCK", outBlock }, { "REPORT", report } }, &ok, &feedback );
  QVERIFY2( ok, qPrintable( feedback.errors.join( '\n' ) ) );
  QGSCOMPARENEAR( result.value( "RMSE_CHECK_M" ).toDouble(), 0.0, 1e-6 );

  const geostation::Block oriented = geostation::Block::load( outBlock.toStdString() );
  const geostation::BlockImage &c = oriented.image( "C" );
  QVERIFY( c.exterior.has_value() );
  const geostation::ExteriorOrientation truth = truthC().exterior();
  QGSCOMPARENEAR( c.exterior->projectionCentre.x(), truth.projectionCentre.x(), 1e-5 );
  QGSCOMPARENEAR( c.exterior->projectionCentre.z(), truth.projectionCentre.z(), 1e-5 );
  QGSCOMPARENEAR( c.exterior->kappaDeg, truth.kappaDeg, 1e-7 );
  QVERIFY( c.exterior->sigma.has_value() );
  QCOMPARE( c.cameraId, std::string( "aerial" ) );
  // Saved in another folder, the image still points at its file.
  QCOMPARE( QFileInfo( QString::fromStdString( oriented.imageFilePath( c ).string() ) ).canonicalFilePath(), QFileInfo( mDir.filePath( "images/C.tif" ) ).canonicalFilePath() );

  QFile reportFile( report );
  QVERIFY( reportFile.open( QIODevice::ReadOnly ) );
  const QJsonObject json = QJsonDocument::fromJson( reportFile.readAll() ).object();
  QVERIFY( json.value( "converged" ).toBool() );
  QVERIFY( json.contains( "sigma0_px" ) );
  QCOMPARE( json.value( "parameters" ).toArray().size(), 6 );
  QCOMPARE( json.value( "parameters" ).toArray().at( 3 ).toObject().value( "unit" ).toString(), QStringLiteral( "deg" ) );
  QCOMPARE( json.value( "correlation" ).toArray().size(), 6 );
  QCOMPARE( json.value( "residuals" ).toArray().size(), 12 );
  QCOMPARE( json.value( "check_count" ).toInt(), 3 );
  QCOMPARE( json.value( "residuals" ).toArray().at( 11 ).toObject().value( "role" ).toString(), QStringLiteral( "check" ) );
}

void TestAdjustmentAlgorithms::resectionWithFreeInteriorGivesTheImageItsOwnCamera()
{
  const QString gcps = write( QStringLiteral( "gcps16.csv" ), groundCsv( 16, 0 ) );
  const QString observations = write( QStringLiteral( "obs-c16.csv" ), observationCsv( { "C" }, 16 ) );
  const QString outBlock = mDir.filePath( QStringLiteral( "free.geostation.json" ) );
  bool ok = false;
  RecordingFeedback feedback;
  run( "resection", { { "BLOCK", mBlockPath }, { "IMAGE", "C" }, { "GCPS", gcps }, { "OBSERVATIONS", observations }, { "FIX", "cx,cy,k1,k2,p1,p2,k3" },
    { "OUTPUT_BLOCK", outBlock }, { "REPORT", mDir.filePath( QStringLiteral( "free.json" ) ) } }, &ok, &feedback );
  QVERIFY2( ok, qPrintable( feedback.errors.join( '\n' ) ) );
  const geostation::Block oriented = geostation::Block::load( outBlock.toStdString() );
  QCOMPARE( oriented.image( "C" ).cameraId, std::string( "aerial@C" ) );
  QCOMPARE( oriented.image( "A" ).cameraId, std::string( "aerial" ) );
  QGSCOMPARENEAR( oriented.camera( "aerial@C" ).f, 1000.0, 1e-5 );
}

void TestAdjustmentAlgorithms::resectionNamesABlunder()
{
  const QString gcps = write( QStringLiteral( "gcps-b.csv" ), groundCsv( 12, 0 ) );
  const QString observations = write( QStringLiteral( "obs-b.csv" ), observationCsv( { "C" }, 12, { { "P5@C", QPointF( 8.0, -5.0 ) } } ) );
  bool ok = false;
  RecordingFeedback feedback;
  const QVariantMap result = run( "resection", { { "BLOCK", mBlockPath }, { "IMAGE", "C" }, { "GCPS", gcps }, { "OBSERVATIONS", observations },
    { "OUTPUT_BLOCK", mDir.filePath( "b.geostation.json" ) }, { "REPORT", mDir.filePath( "b.json" ) }, { "REPORT_HTML", mDir.filePath( "b.html" ) } }, &ok, &feedback );
  QVERIFY2( ok, qPrintable( feedback.errors.join( '\n' ) ) );
  QCOMPARE( result.value( "BLUNDERS" ).toString(), QStringLiteral( "P5" ) );
  QVERIFY( feedback.warnings.join( ' ' ).contains( "P5" ) );

  // the page names the blunder, draws it in red over the frame, and its residual (about the 8, -5 px put in) in the table
  if ( const std::optional<QDir> artifacts = testArtifacts() ) // the user guide's picture of a report
  {
    QFile::remove( artifacts->filePath( "report-resection.html" ) );
    QVERIFY( QFile::copy( mDir.filePath( "b.html" ), artifacts->filePath( "report-resection.html" ) ) );
  }
  const HtmlReportShape page = readHtmlReport( mDir.filePath( "b.html" ) );
  QVERIFY2( page.error.isEmpty(), qPrintable( page.error ) );
  QCOMPARE( page.title, QStringLiteral( "Space resection of C" ) );
  const QStringList blunder = page.row( QStringLiteral( "P5" ) );
  QCOMPARE( blunder.size(), 8 );
  QCOMPARE( blunder.at( 1 ), QStringLiteral( "blunder" ) );
  QVERIFY2( std::abs( blunder.at( 4 ).toDouble() - std::hypot( 8.0, 5.0 ) ) < 0.5, qPrintable( blunder.join( ' ' ) ) );
  QCOMPARE( page.row( QStringLiteral( "P4" ) ).value( 1 ), QStringLiteral( "control" ) );
  QCOMPARE( page.points, 12 );
  QCOMPARE( page.arrows, 1 ); // the other residuals are too small to draw beside it
  QCOMPARE( page.redArrows, 1 );
  QCOMPARE( page.histogramCount, 12 );
  QCOMPARE( page.row( QStringLiteral( "X0" ) ).size(), 4 );
}

void TestAdjustmentAlgorithms::resectionBadInput_data()
{
  QTest::addColumn<int>( "control" );
  QTest::addColumn<QString>( "fix" );
  QTest::addColumn<QString>( "image" );
  QTest::addColumn<QString>( "expected" );
  QTest::newRow( "too few points" ) << 3 << QString() << "C" << "needs at least 4 control points";
  QTest::newRow( "bad FIX" ) << 8 << "f,zoom" << "C" << "\"zoom\" is not an interior parameter";
  QTest::newRow( "unknown image" ) << 8 << QString() << "Q" << "image \"Q\" is not in the block";
  QTest::newRow( "no observations of the image" ) << 8 << QString() << "B" << "no rows for image B";
}

void TestAdjustmentAlgorithms::resectionBadInput()
{
  QFETCH( int, control );
  QFETCH( QString, fix );
  QFETCH( QString, image );
  QFETCH( QString, expected );
  const QString tag = QString( QTest::currentDataTag() ).replace( ' ', '-' );
  const QString gcps = write( QStringLiteral( "gcps-bad-%1.csv" ).arg( tag ), groundCsv( control, 0 ) );
  const QString observations = write( QStringLiteral( "obs-bad-%1.csv" ).arg( tag ), observationCsv( { "C" }, control ) );
  const QString outBlock = mDir.filePath( QStringLiteral( "never.geostation.json" ) );
  const QString report = mDir.filePath( QStringLiteral( "never.json" ) );
  QVariantMap parameters { { "BLOCK", mBlockPath }, { "IMAGE", image }, { "GCPS", gcps }, { "OBSERVATIONS", observations }, { "OUTPUT_BLOCK", outBlock }, { "REPORT", report } };
  if ( !fix.isEmpty() )
    parameters.insert( "FIX", fix );
  bool ok = true;
  RecordingFeedback feedback;
  run( "resection", parameters, &ok, &feedback );
  QVERIFY( !ok );
  QVERIFY2( feedback.errors.join( ' ' ).contains( expected ), qPrintable( feedback.errors.join( '\n' ) ) );
  QVERIFY( !QFile::exists( outBlock ) );
  QVERIFY( !QFile::exists( report ) );
}

namespace
{
  //! The block with A and B moved off their true orientation, as GNSS/INS would give them.
  QString perturbedBlock()
  {
    QString text = QString::fromLatin1( kBlock );
    text.replace( "\"X\": 500000.0, \"Y\": 4400000.0, \"Z\": 1100.0, \"omega\": 0.5", "\"X\": 500000.4, \"Y\": 4399999.7, \"Z\": 1100.3, \"omega\": 0.52" );
    text.replace( "\"X\": 500300.0, \"Y\": 4400010.0, \"Z\": 1102.0, \"omega\": -0.4", "\"X\": 500299.6, \"Y\": 4400010.3, \"Z\": 1101.8, \"omega\": -0.43" );
    // Loose priors: with 1 px ~ 1 m on the ground, the images must dominate.
    text.replace( "\"kappa\": 1.0}", "\"kappa\": 1.0, \"sigma\": {\"X\": 5, \"Y\": 5, \"Z\": 5, \"omega\": 0.5, \"phi\": 0.5, \"kappa\": 0.5}}" );
    text.replace( "\"kappa\": 0.5}", "\"kappa\": 0.5, \"sigma\": {\"X\": 5, \"Y\": 5, \"Z\": 5, \"omega\": 0.5, \"phi\": 0.5, \"kappa\": 0.5}}" );
    return text;
  }
}

void TestAdjustmentAlgorithms::bundleAdjustRecoversThePerturbedBlock()
{
  const QString block = write( QStringLiteral( "perturbed.geostation.json" ), perturbedBlock() );
  QVERIFY( geostation::Block::load( block.toStdString() ).image( "A" ).exterior->sigma.has_value() );
  const QString gcps = write( QStringLiteral( "gcps-ba.csv" ), groundCsv( 6, 4 ) );
  const QString observations = write( QStringLiteral( "obs-ba.csv" ), observationCsv( { "A", "B" }, 16 ) );
  const QString outBlock = mDir.filePath( QStringLiteral( "adjusted.geostation.json" ) );
  const QString report = mDir.filePath( QStringLiteral( "adjusted.json" ) );
  const QString html = mDir.filePath( QStringLiteral( "adjusted.html" ) );
  bool ok = false;
  RecordingFeedback feedback;
  const QVariantMap result = run( "bundle_adjust", { { "BLOCK", block }, { "OBSERVATIONS", observations }, { "GCPS", gcps }, { "SIGMA_PX", 0.05 },
    { "OUTPUT_BLOCK", outBlock }, { "OUTPUT_POINTS", QgsProcessing::TEMPORARY_OUTPUT }, { "REPORT", report }, { "REPORT_HTML", html } }, &ok, &feedback );
  QVERIFY2( ok, qPrintable( feedback.errors.join( '\n' ) ) );
  QGSCOMPARENEAR( result.value( "RMSE_CHECK_M" ).toDouble(), 0.0, 0.01 );

  const geostation::Block adjusted = geostation::Block::load( outBlock.toStdString() );
  const geostation::ExteriorOrientation &a = *adjusted.image( "A" ).exterior;
  // Started 0.4 m off; the 5 m priors still pull by millimetres through the
  // strong X-phi correlation of near-nadir images.
  QGSCOMPARENEAR( a.projectionCentre.x(), 500000.0, 0.01 );
  QGSCOMPARENEAR( a.projectionCentre.y(), 4400000.0, 0.01 );
  QGSCOMPARENEAR( a.projectionCentre.z(), 1100.0, 0.01 );
  QGSCOMPARENEAR( a.omegaDeg, 0.5, 1e-3 );
  QVERIFY( a.sigma->x < 0.1 ); // far better than the GNSS/INS prior
  QVERIFY( !adjusted.image( "C" ).exterior.has_value() ); // not observed: untouched

  QgsVectorLayer *points = qobject_cast<QgsVectorLayer *>( QgsProcessingUtils::mapLayerFromString( result.value( "OUTPUT_POINTS" ).toString(), mContext ) );
  QVERIFY( points );
  QCOMPARE( points->featureCount(), 16LL );
  QCOMPARE( points->crs().authid(), QStringLiteral( "EPSG:32617" ) );
  QgsFeature f;
  QgsFeatureIterator it = points->getFeatures();
  int checks = 0;
  while ( it.nextFeature( f ) )
  {
    const QgsPoint p = *f.geometry().vertices_begin();
    const int i = f.attribute( "point_id" ).toString().mid( 1 ).toInt();
    QGSCOMPARENEAR( p.z(), mPoints[i].z(), 0.01 );
    if ( f.attribute( "role" ).toString() == "check" )
    {
      ++checks;
      QVERIFY( std::abs( f.attribute( "err_z" ).toDouble() ) < 0.01 );
    }
  }
  QCOMPARE( checks, 4 );

  QFile reportFile( report );
  QVERIFY( reportFile.open( QIODevice::ReadOnly ) );
  const QJsonObject json = QJsonDocument::fromJson( reportFile.readAll() ).object();
  QVERIFY( json.value( "converged" ).toBool() );
  QCOMPARE( json.value( "images" ).toArray().size(), 2 );
  QCOMPARE( json.value( "check_count" ).toInt(), 4 );
  QVERIFY( json.value( "rmse_check_m" ).toObject().contains( "planimetric" ) );
  QVERIFY( json.value( "images" ).toArray().at( 0 ).toObject().value( "shift_m" ).toObject().value( "x" ).toDouble() < -0.3 );
  QCOMPARE( json.value( "residuals" ).toArray().size(), 32 );

  // the page a person reads: each image with its RMS, each check point, every residual drawn and counted
  QCOMPARE( result.value( "REPORT_HTML" ).toString(), html );
  const HtmlReportShape page = readHtmlReport( html );
  QVERIFY2( page.error.isEmpty(), qPrintable( page.error ) );
  QCOMPARE( page.title, QStringLiteral( "Bundle adjustment" ) );
  for ( const QString &image : { QStringLiteral( "A" ), QStringLiteral( "B" ) } )
  {
    const QStringList row = page.row( image );
    QVERIFY2( row.size() == 10, qPrintable( image ) );
    QCOMPARE( row.at( 1 ), QStringLiteral( "16" ) );
    QCOMPARE( row.at( 2 ), QString::number( json.value( "images" ).toArray().at( image == "A" ? 0 : 1 ).toObject().value( "rms_px" ).toDouble(), 'f', 3 ) );
  }
  int checkRows = 0, pointRows = 0;
  for ( const QStringList &row : page.rows )
  {
    checkRows += row.size() == 10 && row.at( 1 ) == QLatin1String( "check" );
    pointRows += row.size() == 7 && QStringList( { "tie", "control", "check" } ).contains( row.at( 1 ) );
  }
  QCOMPARE( checkRows, 4 );
  QCOMPARE( pointRows, 16 ); // the points by their RMS: all 16 of this block (at most 20 are listed)
  QCOMPARE( page.points, 32 );
  QVERIFY( page.arrows >= 1 );
  QCOMPARE( page.redArrows, 0 );
  QCOMPARE( page.histogramCount, 32 );
  QCOMPARE( page.svgs, 3 ); // the histogram and one plot per image
}

void TestAdjustmentAlgorithms::bundleAdjustBadInput_data()
{
  QTest::addColumn<QString>( "images" );
  QTest::addColumn<bool>( "priors" );
  QTest::addColumn<int>( "control" );
  QTest::addColumn<QString>( "selfCalibration" );
  QTest::addColumn<QString>( "expected" );
  QTest::newRow( "unoriented image" ) << "A,C" << true << 6 << QString() << "image \"C\" has no exterior orientation";
  QTest::newRow( "no datum" ) << "A,B" << false << 0 << QString() << "no datum";
  QTest::newRow( "bad self-calibration" ) << "A,B" << true << 6 << "f,zoom" << "\"zoom\" is not an interior parameter";
}

void TestAdjustmentAlgorithms::bundleAdjustBadInput()
{
  QFETCH( QString, images );
  QFETCH( bool, priors );
  QFETCH( int, control );
  QFETCH( QString, selfCalibration );
  QFETCH( QString, expected );
  const QString tag = QString( QTest::currentDataTag() ).replace( ' ', '-' );
  const QString block = write( QStringLiteral( "ba-bad-%1.geostation.json" ).arg( tag ), perturbedBlock() );
  const QString observations = write( QStringLiteral( "ba-bad-obs-%1.csv" ).arg( tag ), observationCsv( images.split( ',' ), 12 ) );
  const QString outBlock = mDir.filePath( QStringLiteral( "ba-never.geostation.json" ) );
  const QString report = mDir.filePath( QStringLiteral( "ba-never.json" ) );
  const QString points = mDir.filePath( QStringLiteral( "ba-never.gpkg" ) );
  const QString html = mDir.filePath( QStringLiteral( "ba-never.html" ) );
  QVariantMap parameters { { "BLOCK", block }, { "OBSERVATIONS", observations }, { "USE_POSE_PRIORS", priors },
    { "OUTPUT_BLOCK", outBlock }, { "OUTPUT_POINTS", points }, { "REPORT", report }, { "REPORT_HTML", html } };
  if ( control > 0 )
    parameters.insert( "GCPS", write( QStringLiteral( "ba-bad-gcps-%1.csv" ).arg( tag ), groundCsv( control, 0 ) ) );
  if ( !selfCalibration.isEmpty() )
    parameters.insert( "SELF_CALIBRATION", selfCalibration );
  bool ok = true;
  RecordingFeedback feedback;
  run( "bundle_adjust", parameters, &ok, &feedback );
  QVERIFY( !ok );
  QVERIFY2( feedback.errors.join( ' ' ).contains( expected ), qPrintable( feedback.errors.join( '\n' ) ) );
  QVERIFY( !QFile::exists( outBlock ) );
  QVERIFY( !QFile::exists( report ) );
  QVERIFY( !QFile::exists( html ) );
  QVERIFY( !QFile::exists( points ) );
}

int main( int argc, char **argv )
{
  return runQgisTests<TestAdjustmentAlgorithms>( argc, argv );
}

#include "testadjustmentalgorithms.moc"

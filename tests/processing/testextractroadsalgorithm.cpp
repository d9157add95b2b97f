// geostation:extract_roads on a simulated aerial pair: the verified network
// in both images and in 3-D against the truth centre lines, the same pair
// registered from control points instead of its orientation, and bad
// input failing with one sentence and no file.
#include <algorithm>
#include <QFile>
#include <QJsonArray>
#include <QJsonDocument>
#include <QJsonObject>
#include <QDir>
#include <QTemporaryDir>
#include <QTextStream>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <qgsgeometry.h>
#include <qgsprocessingcontext.h>
#include <qgsprocessingregistry.h>
#include <qgsproject.h>
#include <qgsvectorlayer.h>

#include "geostationprovider.h"
#include "io/block.h"
#include "processingtestutils.h"
#include "simulation/surveysimulator.h"

class TestExtractRoadsAlgorithm : public QObject
{
    Q_OBJECT

  private slots:
    void initTestCase();
    void extractsTheVerifiedNetwork();
    void registersFromControlPoints();
    void badInputFailsWithOneSentence();

  private:
    QVariantMap run( const QVariantMap &parameters, bool *ok, RecordingFeedback *feedback );
    QJsonObject report( const QString &path );
    QTemporaryDir mDir;
    QString mRun;
    QgsProcessingContext mContext;
};

void TestExtractRoadsAlgorithm::initTestCase()
{
  QVERIFY( registerGeoStationProvider() || QgsApplication::processingRegistry()->providerById( "geostation" ) );
  QVERIFY( QgsApplication::processingRegistry()->algorithmById( "geostation:extract_roads" ) );
  mContext.setProject( QgsProject::instance() );
  mRun = mDir.filePath( "aerial" );
  simulateAerialRoadPair( mRun );
}

QVariantMap TestExtractRoadsAlgorithm::run( const QVariantMap &parameters, bool *ok, RecordingFeedback *feedback )
{
  std::unique_ptr<QgsProcessingAlgorithm> alg( QgsApplication::processingRegistry()->algorithmById( "geostation:extract_roads" )->create() );
  return alg->run( parameters, mContext, feedback, ok );
}

QJsonObject TestExtractRoadsAlgorithm::report( const QString &path )
{
  QFile file( path );
  file.open( QIODevice::ReadOnly );
  return QJsonDocument::fromJson( file.readAll() ).object();
}

void TestExtractRoadsAlgorithm::extractsTheVerifiedNetwork()
{
  const QString out = mDir.filePath( "roads.gpkg" ), left = mDir.filePath( "left.gpkg" ), right = mDir.filePath( "right.gpkg" ), ends = mDir.filePath( "ends.gpkg" ),
                json = mDir.filePath( "report.json" );
  RecordingFeedback feedback;
  bool ok = false;
  // the simulator's roads as they are: dark asphalt between bright shoulders, 12-16 px (the defaults, general, are
  // measured on this pair in docs/validation.md; here the parameters that say what the roads look like are checked to count)
  const QVariantMap result = run( { { "BLOCK", mRun + "/block.geostation.json" }, { "LEFT", "S0001" }, { "RIGHT", "S0002" }, { "OUTPUT", out }, { "OUTPUT_LEFT", left },
    { "OUTPUT_RIGHT", right }, { "DEAD_ENDS", ends }, { "REPORT", json }, { "REPORT_HTML", mDir.filePath( "report.html" ) }, { "POLARITY", "dark" },
    { "ROAD_WIDTH_MIN_PX", 6.0 }, { "ROAD_WIDTH_MAX_PX", 20.0 }, { "MIN_CONTRAST", 25.0 } }, &ok, &feedback );
  QVERIFY2( ok, qPrintable( feedback.errors.join( '\n' ) ) );
  QVERIFY( result.value( "LINE_COUNT" ).toInt() >= 3 );
  // the page: every line drawn, every 3-D line in the lengths' histogram
  const HtmlReportShape page = readHtmlReport( mDir.filePath( "report.html" ) );
  QVERIFY2( page.error.isEmpty(), qPrintable( page.error ) );
  QCOMPARE( page.polylines, result.value( "LINE_COUNT" ).toInt() );
  QCOMPARE( page.row( QStringLiteral( "lines in the left image" ) ).value( 1 ).section( ' ', 0, 0 ).toInt(), result.value( "LINE_COUNT" ).toInt() );
  QVERIFY( page.histogramCount > 0 );

  // 3-D lines in the block CRS, near the truth centre lines
  QgsVectorLayer network( out, "network", "ogr" );
  QCOMPARE( network.wkbType(), QgsWkbTypes::LineStringZ );
  QVERIFY( network.featureCount() >= 3 );
  QCOMPARE( network.crs().authid(), QStringLiteral( "EPSG:32617" ) );
  QgsVectorLayer roads( mRun + "/truth.gpkg|layername=roads", "roads", "ogr" );
  QVector<QgsGeometry> centres;
  QgsFeature f;
  QgsFeatureIterator r = roads.getFeatures();
  while ( r.nextFeature( f ) )
    if ( f.attribute( "kind" ).toString() == "centre" )
      centres << f.geometry();
  int near = 0, onRoad = 0, all = 0;
  double length = 0.0;
  QgsFeatureIterator n = network.getFeatures();
  while ( n.nextFeature( f ) )
  {
    QVERIFY( f.attribute( "sigma_max" ).toDouble() > 0.0 );
    QVERIFY( QStringList( { "left", "right", "both" } ).contains( f.attribute( "accepted_in" ).toString() ) );
    length += f.attribute( "length_m" ).toDouble();
    for ( auto v = f.geometry().vertices_begin(); v != f.geometry().vertices_end(); ++v, ++all )
    {
      double d = 1e9;
      for ( const QgsGeometry &c : centres )
        d = std::min( d, c.distance( QgsGeometry( new QgsPoint( ( *v ).x(), ( *v ).y() ) ) ) );
      near += d < 1.0;
      onRoad += d < 3.5;
    }
  }
  QVERIFY2( near >= 0.9 * all, qPrintable( QStringLiteral( "%1 of %2 vertices within 1 m of a centre line (%3 within 3.5 m)" ).arg( near ).arg( all ).arg( onRoad ) ) );
  QVERIFY2( length > 200.0, qPrintable( QString::number( length ) ) );

  // image-space lines: x = col, y = -row
  QgsVectorLayer leftLines( left, "left", "ogr" );
  QVERIFY( leftLines.featureCount() >= 3 );
  QVERIFY( leftLines.crs().authid() != QStringLiteral( "EPSG:32617" ) ); // image space, not the block CRS
  QVERIFY( leftLines.extent().yMaximum() <= 0.0 && leftLines.extent().yMinimum() >= -1024.0 && leftLines.extent().xMinimum() >= 0.0 );
  QgsVectorLayer rightLines( right, "right", "ogr" );
  QVERIFY( rightLines.featureCount() >= 3 );
  if ( const std::optional<QDir> artifacts = testArtifacts() ) // the user guide's picture: OUTPUT_LEFT over the left photo
  {
    cv::Mat photo = cv::imread( ( mRun + "/images/S0001.tif" ).toStdString(), cv::IMREAD_COLOR );
    QVERIFY( !photo.empty() );
    QgsFeatureIterator l = leftLines.getFeatures();
    while ( l.nextFeature( f ) )
    {
      std::vector<cv::Point> points;
      for ( auto v = f.geometry().vertices_begin(); v != f.geometry().vertices_end(); ++v )
        points.emplace_back( cvRound( ( *v ).x() ), cvRound( -( *v ).y() ) );
      cv::polylines( photo, points, false, cv::Scalar( 40, 40, 230 ), 3, cv::LINE_AA );
    }
    cv::Mat small;
    cv::resize( photo, small, cv::Size( 640, 640 ), 0.0, 0.0, cv::INTER_AREA );
    QVERIFY( cv::imwrite( artifacts->filePath( "extraction-left.jpg" ).toStdString(), small, { cv::IMWRITE_JPEG_QUALITY, 85 } ) );
  }

  const QJsonObject rep = report( json );
  QCOMPARE( rep.value( "mapping" ).toString(), QStringLiteral( "orientation" ) );
  QVERIFY( rep.value( "rounds" ).toArray().size() >= 2 );
  QCOMPARE( rep.value( "rounds" ).toArray().at( 0 ).toObject().value( "extracted_in" ).toString(), QStringLiteral( "left" ) );
  QVERIFY( rep.value( "terrain_estimate" ).toObject().value( "points" ).toInt() >= 5 );
  QVERIFY( rep.value( "stages" ).toObject().contains( "verification" ) );
  QVERIFY( !rep.value( "empty" ).toBool() );
  // the pair was read in windows: its 1024 x 1024 images are one sub-image each, 16 tiles of 256 px read once, and
  // small enough to be prepared for matching whole, once each
  const QJsonObject reading = rep.value( "reading" ).toObject();
  QVERIFY( reading.value( "in_windows" ).toBool() );
  QVERIFY( reading.value( "sub_images" ).toInt() >= 2 );
  QCOMPARE( reading.value( "grey_tiles_read" ).toInt(), 32 );
  QCOMPARE( reading.value( "matching_windows" ).toInt(), 2 );
}

void TestExtractRoadsAlgorithm::registersFromControlPoints()
{
  // the simulator's ground control projected into both images by the true orientation
  const geostation::Block truth = geostation::Block::load( ( mRun + "/truth.geostation.json" ).toStdString() );
  const geostation::OrientedImage a = truth.orientedImage( truth.image( "S0001" ) ), b = truth.orientedImage( truth.image( "S0002" ) );
  QgsVectorLayer control( mRun + "/truth.gpkg|layername=control", "control", "ogr" );
  const QString table = mDir.filePath( "control.csv" );
  QFile file( table );
  QVERIFY( file.open( QIODevice::WriteOnly ) );
  QTextStream csv( &file );
  csv << "point_id,col_left,row_left,col_right,row_right\n";
  int pairs = 0;
  QgsFeature f;
  QgsFeatureIterator it = control.getFeatures();
  while ( it.nextFeature( f ) )
  {
    const QgsPoint p( *f.geometry().constGet()->vertices_begin() );
    const Eigen::Vector3d ground( p.x(), p.y(), p.z() );
    const geostation::GroundProjection pa = a.projectGroundToPixel( ground ), pb = b.projectGroundToPixel( ground );
    if ( pa.ok() && pb.ok() && pa.inFrame && pb.inFrame )
    {
      csv << f.attribute( "id" ).toString() << "," << pa.pixelInImage.x() << "," << pa.pixelInImage.y() << "," << pb.pixelInImage.x() << "," << pb.pixelInImage.y() << "\n";
      ++pairs;
    }
  }
  file.close();
  QVERIFY( pairs >= 6 );
  const QString left = mDir.filePath( "cp_left.gpkg" ), right = mDir.filePath( "cp_right.gpkg" ), json = mDir.filePath( "cp_report.json" ), out = mDir.filePath( "cp_3d.gpkg" );
  RecordingFeedback feedback;
  bool ok = false;
  run( { { "BLOCK", mRun + "/block.geostation.json" }, { "LEFT", "S0001" }, { "RIGHT", "S0002" }, { "CONTROL", table }, { "OUTPUT", out }, { "OUTPUT_LEFT", left },
    { "OUTPUT_RIGHT", right }, { "REPORT", json }, { "START_SPACING_PX", 32 } }, &ok, &feedback );
  QVERIFY2( ok, qPrintable( feedback.errors.join( '\n' ) ) );
  const QJsonObject rep = report( json );
  QCOMPARE( rep.value( "mapping" ).toString(), QStringLiteral( "multiquadric" ) );
  QCOMPARE( rep.value( "registration" ).toObject().value( "points" ).toArray().size(), pairs );
  // the verification searches as far as the control points' leave-one-out misregistration calls for
  const double expectedPx = rep.value( "registration" ).toObject().value( "expected_px" ).toDouble();
  QVERIFY( expectedPx > 0.0 );
  QCOMPARE( rep.value( "verification_search_px" ).toDouble(), std::clamp( 2.0 * expectedPx + 2.0, 3.0, 12.0 ) );
  QVERIFY( !QFile::exists( out ) ); // registered by control points: image-space outputs only
  QgsVectorLayer leftLines( left, "left", "ogr" );
  QVERIFY( leftLines.featureCount() >= 3 );
}

void TestExtractRoadsAlgorithm::badInputFailsWithOneSentence()
{
  const QString left = mDir.filePath( "bad_left.gpkg" ), right = mDir.filePath( "bad_right.gpkg" ), json = mDir.filePath( "bad.json" );
  const QVariantMap base { { "BLOCK", mRun + "/block.geostation.json" }, { "LEFT", "S0001" }, { "RIGHT", "S0002" }, { "OUTPUT_LEFT", left }, { "OUTPUT_RIGHT", right }, { "REPORT", json } };
  RecordingFeedback feedback;
  bool ok = true;
  QVariantMap same = base;
  same.insert( "RIGHT", "S0001" );
  run( same, &ok, &feedback );
  QVERIFY( !ok );
  QVERIFY2( feedback.errors.join( ' ' ).contains( "same image" ), qPrintable( feedback.errors.join( '\n' ) ) );

  const QString two = mDir.filePath( "two.csv" );
  QFile file( two );
  QVERIFY( file.open( QIODevice::WriteOnly ) );
  file.write( "point_id,col_left,row_left,col_right,row_right\na,100,100,50,100\nb,900,900,850,900\n" );
  file.close();
  QVariantMap fewPoints = base;
  fewPoints.insert( "CONTROL", two );
  RecordingFeedback feedback2;
  ok = true;
  run( fewPoints, &ok, &feedback2 );
  QVERIFY( !ok );
  QVERIFY2( feedback2.errors.join( ' ' ).contains( "at least 3" ), qPrintable( feedback2.errors.join( '\n' ) ) );
  QVERIFY( !QFile::exists( left ) && !QFile::exists( json ) );

  // no road the parameters describe: empty layers and a report that says so, not an error
  QVariantMap none = base;
  none.insert( "MIN_CONTRAST", 200.0 );
  RecordingFeedback feedback3;
  ok = false;
  const QVariantMap result = run( none, &ok, &feedback3 );
  QVERIFY2( ok, qPrintable( feedback3.errors.join( '\n' ) ) );
  QCOMPARE( result.value( "LINE_COUNT" ).toInt(), 0 );
  QVERIFY( report( json ).value( "empty" ).toBool() );
  QVERIFY( !feedback3.warnings.isEmpty() );
}

int main( int argc, char **argv )
{
  return runQgisTests<TestExtractRoadsAlgorithm>( argc, argv );
}

#include "testextractroadsalgorithm.moc"

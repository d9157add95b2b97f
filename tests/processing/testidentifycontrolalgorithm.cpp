// geostation:identify_control on the simulator's oblique photo: the control
// targets found with no point measured by hand, each at its true pixel; the
// table it writes orients the photo through geostation:resection; heights
// from a DEM for a 2-D control table; bad input failing with one sentence
// and no file.
#include <QFile>
#include <QJsonArray>
#include <QJsonDocument>
#include <QJsonObject>
#include <QTemporaryDir>
#include <QTextStream>

#include <qgsprocessingcontext.h>
#include <qgsprocessingregistry.h>
#include <qgsproject.h>
#include <qgsvectorlayer.h>

#include "geostationprovider.h"
#include "io/block.h"
#include "processingtestutils.h"
#include "simulation/filmscan.h"
#include "simulation/surveysimulator.h"
#include "simulationtruth.h"

class TestIdentifyControlAlgorithm : public QObject
{
    Q_OBJECT

  private slots:
    void initTestCase();
    void identifiesTheTargetsWithoutOrientation();
    void approximateOrientationAndHeightsFromTheDem();
    void scannedFilmThroughItsInnerOrientation();
    void badInputFailsWithOneSentence_data();
    void badInputFailsWithOneSentence();

  private:
    QVariantMap run( const QString &algorithm, const QVariantMap &parameters, bool *ok, RecordingFeedback *feedback );
    QString controlCsv( const QString &name, bool withHeights, int count = 1000, double shiftM = 0.0 );
    //! Checks every identified row against the image truth; returns the number identified.
    int checkAgainstTruth( const QString &table );
    QTemporaryDir mDir;
    QString mRun;
    geostation::TruthTable mTruth;
    QgsProcessingContext mContext;
};

void TestIdentifyControlAlgorithm::initTestCase()
{
  QVERIFY( registerGeoStationProvider() || QgsApplication::processingRegistry()->providerById( "geostation" ) );
  QVERIFY( QgsApplication::processingRegistry()->algorithmById( "geostation:identify_control" ) );
  mContext.setProject( QgsProject::instance() );
  mRun = mDir.filePath( "oblique" );
  geostation::SimulationOptions options;
  options.preset = geostation::SurveyPreset::ObliquePhoto;
  options.outputDir = mRun.toStdString();
  options.imageWidth = 800;
  options.imageHeight = 600;
  options.seed = 8;
  options.degradation.noiseSigma = 2.0;
  geostation::simulateSurvey( options );
  mTruth = geostation::readTruth( ( mRun + "/truth.gpkg" ).toStdString() );
  QVERIFY( mTruth.control.size() >= 20 );
}

QVariantMap TestIdentifyControlAlgorithm::run( const QString &algorithm, const QVariantMap &parameters, bool *ok, RecordingFeedback *feedback )
{
  std::unique_ptr<QgsProcessingAlgorithm> alg( QgsApplication::processingRegistry()->algorithmById( "geostation:" + algorithm )->create() );
  return alg->run( parameters, mContext, feedback, ok );
}

QString TestIdentifyControlAlgorithm::controlCsv( const QString &name, bool withHeights, int count, double shiftM )
{
  QFile file( mDir.filePath( name ) );
  file.open( QIODevice::WriteOnly );
  QTextStream out( &file );
  out << ( withHeights ? "point_id,X,Y,Z\n" : "point_id,X,Y\n" );
  int written = 0;
  for ( const auto &[id, world] : mTruth.control )
  {
    if ( written++ >= count )
      break;
    out << QString::fromStdString( id ) << ',' << QString::number( world.x() + shiftM, 'f', 4 ) << ',' << QString::number( world.y(), 'f', 4 );
    if ( withHeights )
      out << ',' << QString::number( world.z(), 'f', 4 );
    out << '\n';
  }
  return file.fileName();
}

int TestIdentifyControlAlgorithm::checkAgainstTruth( const QString &table )
{
  QgsVectorLayer layer( table, QStringLiteral( "identified" ), QStringLiteral( "ogr" ) );
  if ( !layer.isValid() )
    return -1;
  int identified = 0, flagged = 0, within = 0;
  double worst = 0.0;
  QgsFeature f;
  QgsFeatureIterator it = layer.getFeatures();
  while ( it.nextFeature( f ) )
  {
    if ( f.attribute( "status" ).toString() == QLatin1String( "flagged" ) ) // for the operator to look at: not a measurement
    {
      ++flagged;
      continue;
    }
    if ( f.attribute( "status" ).toString() != QLatin1String( "identified" ) )
    {
      if ( f.attribute( "status" ).toString() != QLatin1String( "not_found" ) || !f.attribute( "col" ).toString().isEmpty() || f.attribute( "pred_col" ).toString().isEmpty() )
      {
        qWarning() << "row of status" << f.attribute( "status" ).toString() << "col" << f.attribute( "col" ) << "pred_col" << f.attribute( "pred_col" );
        return -1;
      }
      continue;
    }
    const auto truth = mTruth.imageTruth.find( { f.attribute( "point_id" ).toString().toStdString(), f.attribute( "image_id" ).toString().toStdString() } );
    if ( truth == mTruth.imageTruth.end() )
    {
      qWarning() << f.attribute( "point_id" ).toString() << "identified, but the photo does not show it";
      return -1;
    }
    const double error = ( Eigen::Vector2d( f.attribute( "col" ).toDouble(), f.attribute( "row" ).toDouble() ) - truth->second ).norm();
    worst = std::max( worst, error );
    within += error <= 0.5 ? 1 : 0; // each mark located again at its prediction, to a fraction of a pixel
    if ( error > 1.5 ) // a wrong identity would be metres away
    {
      qWarning() << f.attribute( "point_id" ).toString() << "identified" << error << "px from its true pixel";
      return -1;
    }
    ++identified;
  }
  qInfo() << identified << "identified," << within << "within 0.5 px, worst" << worst << "px from the true pixel," << flagged << "flagged";
  if ( within < identified )
    return -1;
  return identified;
}

void TestIdentifyControlAlgorithm::identifiesTheTargetsWithoutOrientation()
{
  const geostation::Block block = geostation::Block::load( ( mRun + "/block.geostation.json" ).toStdString() );
  const QString imageId = QString::fromStdString( block.images.front().id );
  const QString out = mDir.filePath( "identified.csv" ), json = mDir.filePath( "identified.json" );
  RecordingFeedback feedback;
  bool ok = false;
  const QVariantMap result = run( QStringLiteral( "identify_control" ), { { "BLOCK", mRun + "/block.geostation.json" }, { "IMAGE", imageId },
    { "CONTROL", controlCsv( QStringLiteral( "control.csv" ), true ) }, { "USE_ORIENTATION", false }, { "OUTPUT", out }, { "REPORT", json },
    { "REPORT_HTML", mDir.filePath( "identified.html" ) } }, &ok, &feedback );
  QVERIFY2( ok, qPrintable( feedback.errors.join( '\n' ) ) );
  const int identified = checkAgainstTruth( out );
  QVERIFY2( identified >= 7, qPrintable( QStringLiteral( "%1 identified" ).arg( identified ) ) );
  QCOMPARE( result.value( "PAIRS_FOUND" ).toInt(), identified );
  QFile reportFile( json );
  QVERIFY( reportFile.open( QIODevice::ReadOnly ) );
  const QJsonObject report = QJsonDocument::fromJson( reportFile.readAll() ).object();
  QCOMPARE( report.value( "pairs_found" ).toInt(), identified );
  QVERIFY( report.value( "false_alarms" ).toDouble() < 0.1 );
  QVERIFY( !report.value( "approximate_orientation_used" ).toBool() );
  // the page: a row and a point per control point found, each with its residual as the JSON has it
  const HtmlReportShape page = readHtmlReport( mDir.filePath( "identified.html" ) );
  QVERIFY2( page.error.isEmpty(), qPrintable( page.error ) );
  int identifiedRows = 0, flaggedRows = 0;
  for ( const QStringList &row : page.rows )
  {
    identifiedRows += row.size() == 7 && row.at( 1 ) == QLatin1String( "identified" );
    flaggedRows += row.size() == 7 && row.at( 1 ) == QLatin1String( "flagged" );
  }
  QCOMPARE( identifiedRows, result.value( "PAIRS_FOUND" ).toInt() );
  QCOMPARE( page.points, identifiedRows + flaggedRows );
  QCOMPARE( page.histogramCount, page.points );
  qInfo() << identified << "targets identified," << report.value( "poses" ).toDouble() << "poses," << report.value( "seconds" ).toDouble() << "s";

  // the table orients the photo through geostation:resection, to the truth's projection centre
  const QString oriented = mDir.filePath( "oriented.geostation.json" );
  RecordingFeedback resectionFeedback;
  run( QStringLiteral( "resection" ), { { "BLOCK", mRun + "/block.geostation.json" }, { "IMAGE", imageId }, { "GCPS", controlCsv( QStringLiteral( "gcps.csv" ), true ) },
    { "OBSERVATIONS", out }, { "OUTPUT_BLOCK", oriented }, { "REPORT", mDir.filePath( "resection.json" ) } }, &ok, &resectionFeedback );
  QVERIFY2( ok, qPrintable( resectionFeedback.errors.join( '\n' ) ) );
  const geostation::Block truth = geostation::Block::load( ( mRun + "/truth.geostation.json" ).toStdString() );
  const double errorM = ( geostation::Block::load( oriented.toStdString() ).images.front().exterior->projectionCentre - truth.images.front().exterior->projectionCentre ).norm();
  qInfo() << "digital photo: projection centre" << errorM << "m from the truth";
  QVERIFY2( errorM < 0.3, qPrintable( QStringLiteral( "projection centre %1 m from the truth" ).arg( errorM ) ) );
}

void TestIdentifyControlAlgorithm::approximateOrientationAndHeightsFromTheDem()
{
  // the block's GNSS/INS orientation (2 m, 0.5 degrees off) narrows the search; the table has no heights
  const geostation::Block block = geostation::Block::load( ( mRun + "/block.geostation.json" ).toStdString() );
  const QString out = mDir.filePath( "guided.csv" ), json = mDir.filePath( "guided.json" );
  RecordingFeedback feedback;
  bool ok = false;
  run( QStringLiteral( "identify_control" ), { { "BLOCK", mRun + "/block.geostation.json" }, { "IMAGE", QString::fromStdString( block.images.front().id ) },
    { "CONTROL", controlCsv( QStringLiteral( "control2d.csv" ), false ) }, { "DEM", mRun + "/terrain.tif" }, { "OUTPUT", out }, { "REPORT", json } }, &ok, &feedback );
  QVERIFY2( ok, qPrintable( feedback.errors.join( '\n' ) ) );
  QVERIFY( checkAgainstTruth( out ) >= 7 );
  QFile reportFile( json );
  QVERIFY( reportFile.open( QIODevice::ReadOnly ) );
  const QJsonObject report = QJsonDocument::fromJson( reportFile.readAll() ).object();
  QVERIFY( report.value( "approximate_orientation_used" ).toBool() );
}

void TestIdentifyControlAlgorithm::scannedFilmThroughItsInnerOrientation()
{
  // a scanned film photo: fiducials found (inner_orientation), control identified in the scan's pixels, then
  // resection through the inner orientation: the workflow of Stokes (1988) with no point clicked
  const QString film = mDir.filePath( "film" );
  geostation::SimulationOptions options;
  options.preset = geostation::SurveyPreset::ObliquePhoto;
  options.scannedFilm = true;
  options.outputDir = film.toStdString();
  options.seed = 8;
  options.degradation.noiseSigma = 2.0;
  geostation::simulateSurvey( options );
  const geostation::TruthTable truth = geostation::readTruth( ( film + "/truth.gpkg" ).toStdString() );
  const geostation::Block block = geostation::Block::load( ( film + "/block.geostation.json" ).toStdString() );
  const QString imageId = QString::fromStdString( block.images.front().id );
  bool ok = false;
  RecordingFeedback innerFeedback;
  const QString inner = mDir.filePath( "film_io.geostation.json" );
  run( QStringLiteral( "inner_orientation" ), { { "BLOCK", film + "/block.geostation.json" }, { "IMAGE", imageId }, { "AUTO", true },
    { "MARK_DIAMETER_PX", geostation::kFiducialDiameterPx }, { "OUTPUT_BLOCK", inner }, { "REPORT", mDir.filePath( "film_io.json" ) } }, &ok, &innerFeedback );
  QVERIFY2( ok, qPrintable( innerFeedback.errors.join( '\n' ) ) );

  const geostation::TruthTable saved = mTruth;
  mTruth = truth;
  const QString out = mDir.filePath( "film_identified.csv" ), gcps = controlCsv( QStringLiteral( "film_control.csv" ), true );
  RecordingFeedback feedback;
  run( QStringLiteral( "identify_control" ), { { "BLOCK", inner }, { "IMAGE", imageId }, { "CONTROL", gcps }, { "USE_ORIENTATION", false }, { "OUTPUT", out } }, &ok, &feedback );
  QVERIFY2( ok, qPrintable( feedback.errors.join( '\n' ) ) );
  const int identified = checkAgainstTruth( out );
  mTruth = saved;
  QVERIFY2( identified >= 7, qPrintable( QStringLiteral( "%1 identified in the scan" ).arg( identified ) ) );

  const QString oriented = mDir.filePath( "film_oriented.geostation.json" );
  RecordingFeedback resectionFeedback;
  run( QStringLiteral( "resection" ), { { "BLOCK", inner }, { "IMAGE", imageId }, { "GCPS", gcps }, { "OBSERVATIONS", out }, { "OUTPUT_BLOCK", oriented },
    { "REPORT", mDir.filePath( "film_resection.json" ) } }, &ok, &resectionFeedback );
  QVERIFY2( ok, qPrintable( resectionFeedback.errors.join( '\n' ) ) );
  const geostation::Block truthBlock = geostation::Block::load( ( film + "/truth.geostation.json" ).toStdString() );
  const double errorM = ( geostation::Block::load( oriented.toStdString() ).images.front().exterior->projectionCentre - truthBlock.images.front().exterior->projectionCentre ).norm();
  qInfo() << "scanned film:" << identified << "identified, projection centre" << errorM << "m from the truth";
  QVERIFY2( errorM < 0.3, qPrintable( QStringLiteral( "projection centre %1 m from the truth" ).arg( errorM ) ) );
}

void TestIdentifyControlAlgorithm::badInputFailsWithOneSentence_data()
{
  QTest::addColumn<QString>( "image" );
  QTest::addColumn<QString>( "control" );
  QTest::addColumn<QString>( "message" );
  const geostation::Block block = geostation::Block::load( ( mRun + "/block.geostation.json" ).toStdString() );
  const QString imageId = QString::fromStdString( block.images.front().id );
  QTest::newRow( "unknown image" ) << "nosuch" << controlCsv( QStringLiteral( "c1.csv" ), true ) << "nosuch";
  QTest::newRow( "three control points" ) << imageId << controlCsv( QStringLiteral( "c3.csv" ), true, 3 ) << "at least 5 are needed";
  QTest::newRow( "control of another site" ) << imageId << controlCsv( QStringLiteral( "far.csv" ), true, 1000, 5000.0 ) << "No control identified";
  QTest::newRow( "no heights, no DEM" ) << imageId << controlCsv( QStringLiteral( "flat.csv" ), false ) << "neither X, Y, Z";
}

void TestIdentifyControlAlgorithm::badInputFailsWithOneSentence()
{
  QFETCH( QString, image );
  QFETCH( QString, control );
  QFETCH( QString, message );
  const QString out = mDir.filePath( QStringLiteral( "bad_%1.csv" ).arg( QTest::currentDataTag() ).replace( ' ', '_' ) );
  RecordingFeedback feedback;
  bool ok = true;
  run( QStringLiteral( "identify_control" ), { { "BLOCK", mRun + "/block.geostation.json" }, { "IMAGE", image }, { "CONTROL", control }, { "OUTPUT", out } }, &ok, &feedback );
  QVERIFY( !ok );
  QVERIFY2( feedback.errors.join( '\n' ).contains( message ), qPrintable( feedback.errors.join( '\n' ) ) );
  QVERIFY( !QFile::exists( out ) );
}

int main( int argc, char **argv )
{
  return runQgisTests<TestIdentifyControlAlgorithm>( argc, argv );
}

#include "testidentifycontrolalgorithm.moc"

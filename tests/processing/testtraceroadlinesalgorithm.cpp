// geostation:trace_road_lines on a simulated highway run: one seed on the
// kerb face traced through the run within a decimetre of the truth, a seed
// in the sky kept with its stop reason, and a table of bad seeds failing
// with one sentence and no file.
#include <QFile>
#include <QTemporaryDir>
#include <QTextStream>

#include <qgsgeometry.h>
#include <qgsprocessingcontext.h>
#include <qgsprocessingregistry.h>
#include <qgsproject.h>
#include <qgsvectorlayer.h>

#include "geostationprovider.h"
#include "processingtestutils.h"
#include "simulation/surveysimulator.h"

class TestTraceRoadLinesAlgorithm : public QObject
{
    Q_OBJECT

  private slots:
    void initTestCase();
    void tracesTheKerbFaceAndKeepsAFailedSeed();
    void allSeedsFailingWritesNothing();

  private:
    QVariantMap run( const QVariantMap &parameters, bool *ok, RecordingFeedback *feedback );
    QString seeds( const QString &name, const QStringList &rows );
    QTemporaryDir mDir;
    QString mRun;
    QgsProcessingContext mContext;
};

void TestTraceRoadLinesAlgorithm::initTestCase()
{
  QVERIFY( registerGeoStationProvider() || QgsApplication::processingRegistry()->providerById( "geostation" ) );
  QVERIFY( QgsApplication::processingRegistry()->algorithmById( "geostation:trace_road_lines" ) );
  mContext.setProject( QgsProject::instance() );
  mRun = mDir.filePath( "run" );
  geostation::SimulationOptions options;
  options.preset = geostation::SurveyPreset::Highway;
  options.outputDir = mRun.toStdString();
  options.stations = 8;
  options.cameras = 2;
  options.degradation.noiseSigma = 2.0;
  options.poseNoiseScale = 0.2;
  geostation::simulateSurvey( options );
}

QVariantMap TestTraceRoadLinesAlgorithm::run( const QVariantMap &parameters, bool *ok, RecordingFeedback *feedback )
{
  std::unique_ptr<QgsProcessingAlgorithm> alg( QgsApplication::processingRegistry()->algorithmById( "geostation:trace_road_lines" )->create() );
  return alg->run( parameters, mContext, feedback, ok );
}

QString TestTraceRoadLinesAlgorithm::seeds( const QString &name, const QStringList &rows )
{
  QFile file( mDir.filePath( name ) );
  file.open( QIODevice::WriteOnly );
  QTextStream out( &file );
  out << "seed_id,image_id,col,row,note\n";
  for ( const QString &r : rows )
    out << r << "\n";
  return file.fileName();
}

void TestTraceRoadLinesAlgorithm::tracesTheKerbFaceAndKeepsAFailedSeed()
{
  // the operator's click: the true pixel of a kerb-face vertex in the lower half of the first image
  QgsVectorLayer truth( mRun + "/truth.gpkg|layername=image_truth", "truth", "ogr" );
  QPointF click;
  QgsFeature f;
  QgsFeatureIterator it = truth.getFeatures();
  while ( it.nextFeature( f ) )
    if ( f.attribute( "image_id" ).toString() == "S0001_FL" && f.attribute( "point_id" ).toString().startsWith( "R1-edge-right-001:" ) && f.attribute( "row" ).toDouble() > 330 &&
         f.attribute( "row" ).toDouble() < 380 )
      click = QPointF( f.attribute( "col" ).toDouble() + 1.0, f.attribute( "row" ).toDouble() );
  QVERIFY( !click.isNull() );
  const QString input = seeds( "seeds.csv", { QStringLiteral( "kerb,S0001_FL,%1,%2,right kerb" ).arg( click.x() ).arg( click.y() ), QStringLiteral( "sky,S0001_FL,320,30,in the sky" ) } );
  const QString output = mDir.filePath( "lines.gpkg" ), vertices = mDir.filePath( "vertices.csv" );
  RecordingFeedback feedback;
  bool ok = false;
  const QVariantMap result = run( { { "BLOCK", mRun + "/block.geostation.json" }, { "SEEDS", input }, { "OUTPUT", output }, { "VERTICES", vertices } }, &ok, &feedback );
  QVERIFY2( ok, qPrintable( feedback.errors.join( '\n' ) ) );
  QCOMPARE( result.value( "TRACED_COUNT" ).toInt(), 1 );
  QCOMPARE( result.value( "FAILED_COUNT" ).toInt(), 1 );
  QVERIFY( !feedback.warnings.isEmpty() );

  QgsVectorLayer lines( output, "lines", "ogr" );
  QCOMPARE( lines.featureCount(), 2L );
  QCOMPARE( lines.wkbType(), QgsWkbTypes::LineStringZ );
  QgsVectorLayer roads( mRun + "/truth.gpkg|layername=roads", "roads", "ogr" );
  QgsGeometry kerb;
  QgsFeatureIterator r = roads.getFeatures();
  while ( r.nextFeature( f ) )
    if ( f.attribute( "id" ).toString() == "R1-edge-right-001" )
      kerb = f.geometry();
  QVERIFY( !kerb.isNull() );
  QgsFeatureIterator l = lines.getFeatures();
  while ( l.nextFeature( f ) )
  {
    if ( f.attribute( "seed_id" ).toString() == "sky" )
    {
      QVERIFY( f.geometry().isEmpty() );
      QCOMPARE( f.attribute( "stop_reason" ).toString(), QStringLiteral( "no_edge" ) );
      QCOMPARE( f.attribute( "note" ).toString(), QStringLiteral( "in the sky" ) ); // input attributes carried
      continue;
    }
    // 8 stations 5 m apart: the kerb face from the click to beyond the last station, every vertex within 0.12 m of the truth
    QCOMPARE( f.attribute( "stop_reason" ).toString(), QStringLiteral( "end_of_run" ) );
    QCOMPARE( f.attribute( "stations" ).toInt(), 8 );
    // (where the last station's line ends moves by a metre or two with its handover: 39.7 m here, just over 40 m from
    // the pairs alone)
    QVERIFY2( f.attribute( "length_m" ).toDouble() > 38.0, qPrintable( f.attribute( "length_m" ).toString() ) );
    QVERIFY( f.attribute( "sigma_max" ).toDouble() > 0.0 );
    int n = 0;
    for ( auto v = f.geometry().vertices_begin(); v != f.geometry().vertices_end(); ++v, ++n )
    {
      const double d = kerb.distance( QgsGeometry( new QgsPoint( ( *v ).x(), ( *v ).y() ) ) );
      QVERIFY2( d < 0.12, qPrintable( QStringLiteral( "vertex %1 is %2 m off the kerb face" ).arg( n ).arg( d ) ) );
    }
    QVERIFY( n >= 20 );
  }
  QgsVectorLayer table( vertices, "vertices", "ogr" );
  QVERIFY( table.featureCount() >= 20 );
}

void TestTraceRoadLinesAlgorithm::allSeedsFailingWritesNothing()
{
  const QString input = seeds( "bad.csv", { "a,S0001_FL,320,20,sky", "b,S0001_FL,300,25,sky" } );
  const QString output = mDir.filePath( "none.gpkg" );
  RecordingFeedback feedback;
  bool ok = true;
  run( { { "BLOCK", mRun + "/block.geostation.json" }, { "SEEDS", input }, { "OUTPUT", output } }, &ok, &feedback );
  QVERIFY( !ok );
  QVERIFY2( feedback.errors.join( ' ' ).contains( "No seed could be traced" ), qPrintable( feedback.errors.join( '\n' ) ) );
  QVERIFY( !QFile::exists( output ) );

  const QString unknown = seeds( "unknown.csv", { "a,S9999_FL,320,300,nowhere" } );
  ok = true;
  RecordingFeedback feedback2;
  run( { { "BLOCK", mRun + "/block.geostation.json" }, { "SEEDS", unknown }, { "OUTPUT", output } }, &ok, &feedback2 );
  QVERIFY( !ok );
  QVERIFY( !QFile::exists( output ) );
}

int main( int argc, char **argv )
{
  return runQgisTests<TestTraceRoadLinesAlgorithm>( argc, argv );
}

#include "testtraceroadlinesalgorithm.moc"

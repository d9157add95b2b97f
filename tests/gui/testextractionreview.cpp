// Reviewing an extracted road network (offscreen): the map tool finds the
// line clicked, a line accepted lands in the current line class with
// method "extracted" and its heights, a rejected one is only marked,
// accepting twice adds nothing, and a point class is refused.
#include <QTemporaryDir>
#include <QtTest/QtTest>

#include <qgsapplication.h>
#include <qgsfeatureiterator.h>
#include <qgsgeometry.h>
#include <qgslinestring.h>
#include <qgsmapcanvas.h>
#include <qgsproject.h>
#include <qgsvectorlayer.h>

#include "extractionreview.h"
#include "featureclass.h"
#include "measurementstore.h"
#include "multiviewsession.h"
#include "reviewtool.h"
#include "simulation/surveysimulator.h"

class TestExtractionReview : public QObject
{
    Q_OBJECT

  private slots:
    void initTestCase();
    void cleanupTestCase();
    void acceptsRejectsAndRefusesTwice();
    void toolFindsTheLineClicked();

  private:
    QgsVectorLayer *extractedLayer();
    QTemporaryDir mDir;
    std::unique_ptr<GeoStationMultiviewSession> mSession;
    std::unique_ptr<GeoStationMeasurementStore> mStore;
};

void TestExtractionReview::initTestCase()
{
  geostation::SimulationOptions options;
  options.preset = geostation::SurveyPreset::AerialStereo;
  options.stations = 2;
  options.imageWidth = options.imageHeight = 256;
  options.groundPixelSizeM = 1.0;
  options.outputDir = mDir.filePath( "pair" ).toStdString();
  geostation::simulateSurvey( options );
  mSession = std::make_unique<GeoStationMultiviewSession>();
  QString error;
  QVERIFY2( mSession->openBlock( mDir.filePath( "pair/block.geostation.json" ), &error ), qPrintable( error ) );
  mSession->setTargetGeoPackage( mDir.filePath( "measurements.gpkg" ) );
  QList<GeoStationFeatureClass> classes;
  QVERIFY( GeoStationFeatureClass::fromJson( QStringLiteral( R"([{"name":"Road centre","geometry":"line"},{"name":"Pole","geometry":"point"}])" ), classes, &error ) );
  mSession->setFeatureClasses( classes );
  mStore = std::make_unique<GeoStationMeasurementStore>( mSession.get(), QgsProject::instance() );
}

void TestExtractionReview::cleanupTestCase()
{
  mStore.reset();
  mSession.reset();
  QgsProject::instance()->clear();
}

QgsVectorLayer *TestExtractionReview::extractedLayer()
{
  // as geostation:extract_roads writes it: two 3-D lines
  QgsVectorLayer *layer = new QgsVectorLayer( QStringLiteral( "LineStringZ?crs=EPSG:32617&field=line_id:integer&field=accepted_in:string&field=length_m:double&field=sigma_max:double" ),
                                              QStringLiteral( "roads 3d" ), QStringLiteral( "memory" ) );
  QgsFeature a( layer->fields() ), b( layer->fields() );
  a.setAttributes( QgsAttributes() << 1 << "right" << 100.0 << 0.4 );
  a.setGeometry( QgsGeometry( new QgsLineString( QVector<double> { 500000, 500100 }, QVector<double> { 4400000, 4400000 }, QVector<double> { 201.5, 202.0 } ) ) );
  b.setAttributes( QgsAttributes() << 2 << "both" << 80.0 << 0.6 );
  b.setGeometry( QgsGeometry( new QgsLineString( QVector<double> { 500000, 500000 }, QVector<double> { 4400020, 4400100 }, QVector<double> { 200.0, 199.0 } ) ) );
  layer->dataProvider()->addFeatures( QgsFeatureList() << a << b );
  QgsProject::instance()->addMapLayer( layer );
  return layer;
}

void TestExtractionReview::acceptsRejectsAndRefusesTwice()
{
  QgsVectorLayer *layer = extractedLayer();
  QVERIFY( GeoStationExtractionReview::isExtractedRoadsLayer( layer ) );
  GeoStationExtractionReview review( mSession.get(), mStore.get() );
  QStringList messages;
  connect( &review, &GeoStationExtractionReview::message, this, [&]( const QString &text, bool ) { messages << text; } );

  // a point class cannot take a road
  mSession->setCurrentClass( QStringLiteral( "Pole" ) );
  QVERIFY( !review.review( layer, 1, true ) );
  QVERIFY( messages.last().contains( "line class" ) );

  mSession->setCurrentClass( QStringLiteral( "Road centre" ) );
  QVERIFY2( review.review( layer, 1, true ), qPrintable( messages.join( '\n' ) ) );
  QVERIFY( review.review( layer, 2, false ) );
  QVERIFY( !review.review( layer, 1, true ) ); // twice: nothing added
  QVERIFY( messages.last().contains( "already" ) );

  QString error;
  QgsVectorLayer *roads = mStore->layerFor( *mSession->findClass( QStringLiteral( "Road centre" ) ), &error );
  QVERIFY2( roads, qPrintable( error ) );
  QCOMPARE( roads->featureCount(), 1L );
  QgsFeature f;
  QVERIFY( roads->getFeatures().nextFeature( f ) );
  QCOMPARE( f.attribute( "method" ).toString(), QStringLiteral( "extracted" ) );
  QCOMPARE( f.geometry().constGet()->vertexAt( QgsVertexId( 0, 0, 1 ) ).z(), 202.0 );
  QCOMPARE( f.attribute( "sigma_z" ).toDouble(), 0.4 );

  QgsFeature one, two;
  QVERIFY( layer->getFeature( 1 ).isValid() );
  one = layer->getFeature( 1 );
  two = layer->getFeature( 2 );
  QCOMPARE( one.attribute( "review" ).toString(), QStringLiteral( "accepted" ) );
  QCOMPARE( two.attribute( "review" ).toString(), QStringLiteral( "rejected" ) );
}

void TestExtractionReview::toolFindsTheLineClicked()
{
  QgsVectorLayer *layer = extractedLayer();
  QgsMapCanvas canvas;
  canvas.setDestinationCrs( QgsCoordinateReferenceSystem( QStringLiteral( "EPSG:32617" ) ) );
  canvas.setLayers( { layer } );
  QgsVectorLayer *found = nullptr;
  QgsFeatureId fid = FID_NULL;
  QVERIFY( GeoStationReviewTool::lineAt( &canvas, QgsPointXY( 500050, 4400000.8 ), 2.0, found, fid ) );
  QCOMPARE( found, layer );
  QCOMPARE( fid, 1LL );
  QVERIFY( GeoStationReviewTool::lineAt( &canvas, QgsPointXY( 500000.5, 4400060 ), 2.0, found, fid ) );
  QCOMPARE( fid, 2LL );
  QVERIFY( !GeoStationReviewTool::lineAt( &canvas, QgsPointXY( 500060, 4400060 ), 2.0, found, fid ) );
}

int main( int argc, char **argv )
{
  QgsApplication app( argc, argv, true );
  QgsApplication::init();
  QgsApplication::initQgis();
  int result = 0;
  {
    TestExtractionReview test;
    result = QTest::qExec( &test, argc, argv );
  }
  QgsApplication::exitQgis();
  return result;
}

#include "testextractionreview.moc"

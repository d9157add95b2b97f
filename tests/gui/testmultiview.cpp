// The Multiview without QGIS desktop (offscreen): session navigation and
// project round trip, feature classes, measuring a pole foot into the
// GeoPackage through the edit buffer (checked against the simulator's
// truth), lines, undo, a read-only GeoPackage, the operator's own edit
// session, the views (placeholder for a missing image, enhancement in
// memory, features drawn back into the images), the Overview layers, the
// Trace tool (a kerb traced through the run into its layer, against truth)
// and a map revision's change shown in the images that see it.
#include <QFile>
#include <csignal>

#include <sys/resource.h>
#include <QLabel>
#include <QMainWindow>
#include <QRegularExpression>
#include <QTemporaryDir>
#include <QtTest/QtTest>

#include <gdal.h>
#include <ogr_api.h>

#include <qgsapplication.h>
#include <qgsfeatureiterator.h>
#include <qgslinestring.h>
#include <qgsmapcanvas.h>
#include <qgsmapmouseevent.h>
#include <qgsproject.h>
#include <qgsrasterlayer.h>
#include <qgsvectorlayer.h>
#include <qgsvectorfilewriter.h>
#include <qgsvectorlayereditbuffer.h>

#include <qgsprocessingcontext.h>
#include <qgsprocessingfeedback.h>

#include "exportmeasurementsalgorithm.h"
#include "changeinimages.h"
#include "featureclassmodel.h"
#include "imagepointtool.h"
#include "imageview.h"
#include "measurementcontroller.h"
#include "measurementstore.h"
#include "multiviewdock.h"
#include "multiviewsession.h"
#include "overviewlayers.h"
#include "simulation/surveysimulator.h"
#include "simulationtruth.h"
#include "linescoring.h"
#include "tracebar.h"
#include "tracecontroller.h"

class TestMultiview : public QObject
{
    Q_OBJECT

  private slots:
    void initTestCase();
    void init();
    void cleanupTestCase();
    void navigationKeepsEachViewOnItsCamera();
    void sessionRoundTripsThroughTheProject();
    void featureClassesValidate();
    void measuringAPoleFootWritesItWithinThreeSigma();
    void linesUndoAndSingleRayVertices();
    void singleImageVertexOnTheDem();
    void readOnlyGeoPackageIsReportedBeforeMeasuring();
    void operatorEditSessionKeepsUndo();
    void failedWriteKeepsTheFeatureInTheEditBuffer();
    void removedGeoPackageLosesNothing();
    void fullDiskKeepsTheFeatureUntilThereIsRoom();
    void pluginUnloadedWithEditsPendingKeepsTheirVertices();
    void imageDeletedWhileItsViewIsOpen();
    void blockFileChangedOnDiskIsReadAgain();
    void viewsShowPlaceholdersEnhancementsAndFeatures();
    void navigationPreparesTheStationAndTheNextForMatching();
    void photosAreShownInTheirPixelsTurnedAsTagged();
    void exportWritesShapefileAndDxfWithAttributesAndZ();
    void viewsMoveBetweenTheGridAndDocksOfTheirOwn();
    void overviewShowsRunStationsAndCones();
    void traceToolTracesStopsTakesBackAndWritesOneLine();
    void aReviewedChangeIsShownInTheImagesThatSeeIt();

  private:
    //! A pole seen in the first two images of a station, with its truth pixels; false if none.
    //! A pole seen in the first two images of the current station, with its truth pixels; false if none.
    bool findPole( QString &id, QPointF &left, QPointF &right, Eigen::Vector3d &truth ) const;
    //! Steps to the first station (from `from`) with such a pole; false if there is none.
    bool goToStationWithPole( QString &id, QPointF &left, QPointF &right, Eigen::Vector3d &truth, int from = 0 );
    //! Steps to the first station (from `from`) with a pole, clicks its foot in view 0 and accepts the point; false if none or refused.
    bool measurePoleFrom( int from );
    /**
     * As measurePoleFrom(), with the disk full: simulated by a file size limit
     * for this process, so a write past 4 kB of any file fails (EFBIG, as a
     * full disk fails with ENOSPC) and SQLite cannot write the GeoPackage or
     * its journal. The limit is lifted before it returns.
     */
    bool measurePoleWithDiskFull( int from );
    QString measurementsPath() const { return mDir.filePath( QStringLiteral( "measurements.gpkg" ) ); }

    QTemporaryDir mDir;
    QString mBlockPath;
    geostation::TruthTable mTruth;
    std::unique_ptr<GeoStationMultiviewSession> mSession;
    std::unique_ptr<GeoStationMeasurementStore> mStore;
    std::unique_ptr<GeoStationMeasurementController> mController;
};

void TestMultiview::initTestCase()
{
  QVERIFY( mDir.isValid() );
  geostation::SimulationOptions options;
  options.preset = geostation::SurveyPreset::Highway;
  options.seed = 7;
  options.stations = 10;
  options.degradation.noiseSigma = 1.0;
  options.outputDir = mDir.filePath( QStringLiteral( "run" ) ).toStdString();
  geostation::simulateSurvey( options );
  mBlockPath = mDir.filePath( QStringLiteral( "run/truth.geostation.json" ) );
  mTruth = geostation::readTruth( options.outputDir / "truth.gpkg" );
}

void TestMultiview::init()
{
  mController.reset();
  mStore.reset();
  QgsProject::instance()->clear();
  QFile::remove( measurementsPath() );
  mSession = std::make_unique<GeoStationMultiviewSession>();
  QString error;
  QVERIFY2( mSession->openBlock( mBlockPath, &error ), qPrintable( error ) );
  mSession->setTargetGeoPackage( measurementsPath() );
  QList<GeoStationFeatureClass> classes;
  QVERIFY( GeoStationFeatureClass::fromJson( QStringLiteral( R"([{"name":"Pole","geometry":"point","attributes":{"kind":"pole"}},
                                                                {"name":"Kerb line","geometry":"line"}])" ), classes, &error ) );
  mSession->setFeatureClasses( classes );
  mStore = std::make_unique<GeoStationMeasurementStore>( mSession.get(), QgsProject::instance() );
  mController = std::make_unique<GeoStationMeasurementController>( mSession.get(), mStore.get() );
}

void TestMultiview::cleanupTestCase()
{
  mController.reset();
  mStore.reset();
  mSession.reset();
  QgsProject::instance()->clear();
}

bool TestMultiview::findPole( QString &id, QPointF &left, QPointF &right, Eigen::Vector3d &truth ) const
{
  const QStringList images = mSession->viewImages();
  for ( const auto &[pointId, point] : mTruth.objects )
  {
    if ( pointId.rfind( "pole_", 0 ) != 0 )
      continue;
    const auto l = mTruth.imageTruth.find( { pointId, images[0].toStdString() } );
    const auto r = mTruth.imageTruth.find( { pointId, images[1].toStdString() } );
    if ( l == mTruth.imageTruth.end() || r == mTruth.imageTruth.end() )
      continue;
    if ( ( point - mSession->orientedImage( images[0] )->exterior().projectionCentre ).norm() > 32.0 )
      continue;
    id = QString::fromStdString( pointId );
    left = QPointF( l->second.x(), l->second.y() );
    right = QPointF( r->second.x(), r->second.y() );
    truth = point;
    return true;
  }
  return false;
}

bool TestMultiview::goToStationWithPole( QString &id, QPointF &left, QPointF &right, Eigen::Vector3d &truth, int from )
{
  for ( int station = from; station < mSession->run().size(); ++station )
  {
    mSession->setCurrentStation( station );
    if ( findPole( id, left, right, truth ) )
    {
      mController->viewsChanged();
      return true;
    }
  }
  return false;
}

bool TestMultiview::measurePoleWithDiskFull( int from )
{
  rlimit unlimited {};
  if ( getrlimit( RLIMIT_FSIZE, &unlimited ) != 0 )
    return false;
  const auto previousHandler = std::signal( SIGXFSZ, SIG_IGN );
  rlimit full = unlimited;
  full.rlim_cur = 4096;
  const bool limited = setrlimit( RLIMIT_FSIZE, &full ) == 0;
  const bool accepted = limited && measurePoleFrom( from );
  const bool lifted = setrlimit( RLIMIT_FSIZE, &unlimited ) == 0;
  std::signal( SIGXFSZ, previousHandler );
  return accepted && lifted;
}

bool TestMultiview::measurePoleFrom( int from )
{
  QString id;
  QPointF left, right;
  Eigen::Vector3d truth;
  if ( !goToStationWithPole( id, left, right, truth, from ) )
    return false;
  mController->pick( 0, left );
  return mController->acceptPoint();
}

void TestMultiview::navigationKeepsEachViewOnItsCamera()
{
  QCOMPARE( mSession->run().size(), 10 );
  QCOMPARE( mSession->viewCount(), 3 );
  QCOMPARE( mSession->viewImages(), QStringList( { "S0001_FL", "S0001_FR", "S0001_SR" } ) );
  QSignalSpy changed( mSession.get(), &GeoStationMultiviewSession::stationChanged );
  mSession->stepStation( 1 );
  QCOMPARE( mSession->viewImages(), QStringList( { "S0002_FL", "S0002_FR", "S0002_SR" } ) );
  mSession->stepStation( 10 );
  QCOMPARE( mSession->currentStationId(), QStringLiteral( "S0010" ) );
  mSession->stepStation( 1 ); // the end of the run: no change
  QCOMPARE( changed.count(), 2 );
  // a pair across stations: view 2 shows the next station's front-left image
  mSession->setCurrentStation( 2 );
  QVERIFY( mSession->setViewImage( 1, QStringLiteral( "S0004_FL" ) ) );
  QCOMPARE( mSession->viewImages(), QStringList( { "S0003_FL", "S0004_FL", "S0003_SR" } ) );
  mSession->stepStation( 1 );
  QCOMPARE( mSession->viewImages(), QStringList( { "S0004_FL", "S0005_FL", "S0004_SR" } ) );
  mSession->setCurrentStation( 9 );
  QCOMPARE( mSession->viewImages().at( 1 ), QString() ); // past the end of the run
  QVERIFY( !mSession->setViewImage( 0, QStringLiteral( "nope" ) ) );
  mSession->setViewCount( 5 );
  QCOMPARE( mSession->viewImages().size(), 5 );
}

void TestMultiview::sessionRoundTripsThroughTheProject()
{
  mSession->setCurrentStation( 4 );
  mSession->setViewImage( 2, QStringLiteral( "S0006_FR" ) );
  mSession->setCurrentClass( QStringLiteral( "Kerb line" ) );
  mSession->setRoadPlane( 2.4, 0.03 );
  QgsProject project;
  project.setFileName( mDir.filePath( QStringLiteral( "session.qgz" ) ) );
  mSession->writeToProject( &project );
  QVERIFY( project.write() );

  QgsProject reread;
  QVERIFY( reread.read( mDir.filePath( QStringLiteral( "session.qgz" ) ) ) );
  GeoStationMultiviewSession restored;
  QString error;
  QVERIFY( restored.readFromProject( &reread, &error ) );
  QVERIFY2( error.isEmpty(), qPrintable( error ) );
  QCOMPARE( restored.blockPath(), QFileInfo( mBlockPath ).absoluteFilePath() );
  QCOMPARE( restored.currentStationId(), QStringLiteral( "S0005" ) );
  QCOMPARE( restored.viewImages(), mSession->viewImages() );
  QCOMPARE( restored.featureClasses(), mSession->featureClasses() );
  QCOMPARE( restored.currentClass(), QStringLiteral( "Kerb line" ) );
  QCOMPARE( restored.targetGeoPackage(), QFileInfo( measurementsPath() ).absoluteFilePath() );
  QCOMPARE( restored.cameraHeightAboveRoadM(), 2.4 );
  QCOMPARE( restored.roadPlaneSigmaM(), 0.03 );

  // a project without GeoStation state leaves the session alone
  QgsProject empty;
  QVERIFY( !restored.readFromProject( &empty, &error ) );
  // a block that has gone: said once, the rest restored
  QgsProject moved;
  mSession->writeToProject( &moved );
  moved.writeEntry( QStringLiteral( "GeoStation" ), QStringLiteral( "block" ), mDir.filePath( QStringLiteral( "gone.geostation.json" ) ) );
  GeoStationMultiviewSession orphan;
  QVERIFY( orphan.readFromProject( &moved, &error ) );
  QVERIFY2( error.contains( QStringLiteral( "gone.geostation.json" ) ), qPrintable( error ) );
  QCOMPARE( orphan.featureClasses().size(), 2 );
  QVERIFY( !orphan.hasBlock() );
}

void TestMultiview::featureClassesValidate()
{
  QList<GeoStationFeatureClass> classes;
  QString error;
  QVERIFY( !GeoStationFeatureClass::fromJson( QStringLiteral( R"([{"name":"a","geometry":"curve"}])" ), classes, &error ) );
  QVERIFY( error.contains( QStringLiteral( "point, line or polygon" ) ) );
  QVERIFY( !GeoStationFeatureClass::fromJson( QStringLiteral( R"([{"name":"A b","geometry":"point"},{"name":"a-b","geometry":"line"}])" ), classes, &error ) );
  QVERIFY( error.contains( QStringLiteral( "a_b" ) ) );
  QVERIFY( !GeoStationFeatureClass::fromJson( QStringLiteral( R"([{"name":"x","geometry":"point","attributes":{"sigma_x":"1"}}])" ), classes, &error ) );
  QVERIFY( !GeoStationFeatureClass::fromJson( QStringLiteral( "{" ), classes, &error ) );
  GeoStationFeatureClassModel model;
  model.setClasses( mSession->featureClasses() );
  QCOMPARE( model.rowCount(), 2 );
  QCOMPARE( model.data( model.index( 0, static_cast<int>( GeoStationFeatureClassModel::Column::Attributes ) ) ).toString(), QStringLiteral( "kind=pole" ) );
  QVERIFY( model.setData( model.index( 1, static_cast<int>( GeoStationFeatureClassModel::Column::Attributes ) ), QStringLiteral( "material=granite; height=0.15" ) ) );
  QVERIFY( !model.setData( model.index( 1, static_cast<int>( GeoStationFeatureClassModel::Column::Attributes ) ), QStringLiteral( "no equals sign" ) ) );
  QCOMPARE( model.classes().at( 1 ).attributes.value( QStringLiteral( "height" ) ).toString(), QStringLiteral( "0.15" ) );
  const int row = model.addClass( GeoStationFeatureClass::Geometry::Polygon );
  QCOMPARE( model.classes().at( row ).name, QStringLiteral( "polygon_1" ) );
  QVERIFY( model.validate( &error ) );
}

void TestMultiview::measuringAPoleFootWritesItWithinThreeSigma()
{
  int measured = 0;
  QString id;
  QPointF left, right;
  Eigen::Vector3d truth;
  for ( int from = 0; measured < 3 && goToStationWithPole( id, left, right, truth, from ); from = mSession->currentStation() + 1 )
  {
    mController->pick( 0, left );
    QVERIFY( mController->hasOpenPoint() );
    const auto &states = mController->viewStates();
    QVERIFY( !states[1].curve.pieces.empty() );
    QVERIFY2( states[1].proposed, qPrintable( states[1].status ) );
    QVERIFY2( QLineF( states[1].pixel, right ).length() < 1.0, qPrintable( QStringLiteral( "%1: proposal %2 px off" ).arg( id ).arg( QLineF( states[1].pixel, right ).length() ) ) );
    QSignalSpy written( mController.get(), &GeoStationMeasurementController::featureWritten );
    QVERIFY( mController->acceptPoint() );
    QCOMPARE( written.count(), 1 ); // a point class finishes at once
    QCOMPARE( mController->vertexCount(), 0 );

    QgsVectorLayer *layer = mStore->measurementLayers().value( 0 );
    QVERIFY( layer );
    QVERIFY( !layer->isEditable() );
    QgsFeature last;
    QgsFeatureIterator it = layer->getFeatures();
    QgsFeature f;
    int count = 0;
    while ( it.nextFeature( f ) )
    {
      last = f;
      ++count;
    }
    QCOMPARE( count, measured + 1 );
    const QgsPoint *p = qgsgeometry_cast<const QgsPoint *>( last.geometry().constGet() );
    QVERIFY( p && p->is3D() );
    const Eigen::Vector3d error = Eigen::Vector3d( p->x(), p->y(), p->z() ) - truth;
    const Eigen::Vector3d sigma( last.attribute( "sigma_x" ).toDouble(), last.attribute( "sigma_y" ).toDouble(), last.attribute( "sigma_z" ).toDouble() );
    qInfo() << id << "error" << error.x() << error.y() << error.z() << "sigma" << sigma.x() << sigma.y() << sigma.z();
    for ( int k = 0; k < 3; ++k )
      QVERIFY2( std::abs( error[k] ) < 3 * sigma[k], qPrintable( QStringLiteral( "%1: error %2 m, sigma %3 m" ).arg( id ).arg( error[k] ).arg( sigma[k] ) ) );
    QCOMPARE( last.attribute( "class" ).toString(), QStringLiteral( "Pole" ) );
    QCOMPARE( last.attribute( "kind" ).toString(), QStringLiteral( "pole" ) );
    QCOMPARE( last.attribute( "station" ).toString(), mSession->currentStationId() );
    QCOMPARE( last.attribute( "method" ).toString(), QStringLiteral( "intersection" ) );
    QVERIFY( last.attribute( "n_images" ).toInt() >= 2 );
    QVERIFY( last.attribute( "acquired" ).toString().startsWith( QLatin1String( "20" ) ) );
    QVERIFY( !last.attribute( "measured" ).toString().isEmpty() );

    // the vertex record, linked by the committed fid
    QString error2;
    QgsVectorLayer *vertices = mStore->verticesTable( &error2 );
    QVERIFY2( vertices, qPrintable( error2 ) );
    QgsFeatureRequest request;
    request.setFilterExpression( QStringLiteral( "feature_fid = %1 AND layer = 'pole'" ).arg( last.id() ) );
    QgsFeatureIterator vit = vertices->getFeatures( request );
    QgsFeature v;
    QVERIFY( vit.nextFeature( v ) );
    QCOMPARE( v.attribute( "vertex" ).toInt(), 0 );
    QCOMPARE( v.attribute( "X" ).toDouble(), p->x() );
    QVERIFY( v.attribute( "image_ids" ).toString().contains( mSession->viewImages().at( 0 ) ) );
    QCOMPARE( v.attribute( "residuals_px" ).toString().split( ';' ).size(), v.attribute( "image_ids" ).toString().split( ';' ).size() );
    QVERIFY( !vit.nextFeature( v ) );
    ++measured;
  }
  QVERIFY( measured >= 2 );
}

void TestMultiview::linesUndoAndSingleRayVertices()
{
  mSession->setCurrentClass( QStringLiteral( "Kerb line" ) );
  mSession->setCurrentStation( 1 );
  mController->viewsChanged();
  // the side camera alone: road-plane vertices below the van
  const QStringList images = mSession->viewImages();
  QSignalSpy messages( mController.get(), &GeoStationMeasurementController::message );
  for ( const QPointF &pixel : { QPointF( 200, 400 ), QPointF( 300, 420 ), QPointF( 400, 440 ) } )
  {
    mController->pick( 2, pixel );
    // nothing matched in the front cameras for a point beside the van: one ray
    QVERIFY( mController->acceptPoint() );
  }
  QCOMPARE( mController->vertexCount(), 3 );
  QCOMPARE( mController->currentFeature().vertices.last().method, geostation::VertexMethod::RoadPlane );
  const double roadZ = mSession->orientedImage( images[2] )->exterior().projectionCentre.z() - mSession->cameraHeightAboveRoadM();
  QVERIFY( std::abs( mController->currentFeature().vertices.last().point.z() - roadZ ) < 1e-6 );
  mController->undoVertex();
  QCOMPARE( mController->vertexCount(), 2 );
  mController->pick( 2, QPointF( 500, 450 ) );
  mController->undoVertex(); // takes back the open point first
  QVERIFY( !mController->hasOpenPoint() );
  QCOMPARE( mController->vertexCount(), 2 );
  QVERIFY( mController->finishFeature() );
  QgsVectorLayer *layer = nullptr;
  for ( QgsVectorLayer *l : mStore->measurementLayers() )
    if ( l->name() == QLatin1String( "kerb_line" ) )
      layer = l;
  QVERIFY( layer );
  QCOMPARE( layer->featureCount(), 1L );
  QgsFeature f;
  layer->getFeatures().nextFeature( f );
  QCOMPARE( f.geometry().constGet()->nCoordinates(), 2 );
  QCOMPARE( f.attribute( "method" ).toString(), QStringLiteral( "road-plane" ) );
  QCOMPARE( f.attribute( "n_images" ).toInt(), 1 );
  // a line needs two vertices
  mController->pick( 2, QPointF( 200, 400 ) );
  QVERIFY( mController->acceptPoint() );
  QVERIFY( !mController->finishFeature() );
  QCOMPARE( mController->vertexCount(), 1 ); // kept
}

void TestMultiview::singleImageVertexOnTheDem()
{
  // the run's terrain as the DEM layer: a point on the ground measured in one image is monoplotted
  QgsRasterLayer *dem = new QgsRasterLayer( mDir.filePath( QStringLiteral( "run/terrain.tif" ) ), QStringLiteral( "terrain" ) );
  QVERIFY( dem->isValid() );
  QgsProject::instance()->addMapLayer( dem );
  mSession->setDemLayerId( dem->id() );
  mSession->setCurrentClass( QStringLiteral( "Kerb line" ) ); // vertices stay in the feature
  // one view: the front-left camera alone
  mSession->setViewCount( 1 );
  int measured = 0;
  for ( int station = 0; station < mSession->run().size() && measured < 3; ++station )
  {
    mSession->setCurrentStation( station );
    const QString side = QString::fromStdString( mSession->run().at( station ).imageIds.front() );
    QVERIFY( mSession->setViewImage( 0, side ) );
    mController->viewsChanged();
    // truth points on the ground: pole and hydrant feet, manhole lids (a sign's is its panel)
    for ( const auto &[pointId, point] : mTruth.objects )
    {
      const auto pixel = mTruth.imageTruth.find( { pointId, side.toStdString() } );
      if ( pixel == mTruth.imageTruth.end() || pointId.rfind( "sign_", 0 ) == 0 )
        continue;
      mController->pick( 0, QPointF( pixel->second.x(), pixel->second.y() ) );
      QVERIFY( mController->acceptPoint() );
      const geostation::MeasuredVertex *v = mController->lastVertex();
      QVERIFY( v );
      QCOMPARE( v->method, geostation::VertexMethod::MonoplotDem );
      const Eigen::Vector3d error = v->point - point;
      qInfo() << QString::fromStdString( pointId ) << "DEM vertex error" << error.x() << error.y() << error.z() << "sigma" << v->sigmaM.x() << v->sigmaM.y() << v->sigmaM.z();
      for ( int k = 0; k < 3; ++k )
        QVERIFY( std::abs( error[k] ) < 3 * v->sigmaM[k] + 0.005 );
      QVERIFY( v->sigmaM.norm() > 0 );
      ++measured;
      break;
    }
  }
  QVERIFY( measured >= 1 );
}

void TestMultiview::readOnlyGeoPackageIsReportedBeforeMeasuring()
{
  // create the file, then make it read-only
  QString error;
  QVERIFY2( mStore->layerFor( mSession->featureClasses().at( 0 ), &error ), qPrintable( error ) );
  QgsProject::instance()->clear();
  QFile file( measurementsPath() );
  QVERIFY( file.setPermissions( QFileDevice::ReadOwner | QFileDevice::ReadGroup ) );
  QVERIFY( !mStore->checkWritable( &error ) );
  QVERIFY( error.contains( QStringLiteral( "read-only" ) ) );
  QSignalSpy messages( mController.get(), &GeoStationMeasurementController::message );
  mController->viewsChanged();
  mController->pick( 0, QPointF( 300, 300 ) );
  QVERIFY( !mController->hasOpenPoint() );
  QCOMPARE( messages.count(), 1 );
  QVERIFY( messages.at( 0 ).at( 0 ).toString().contains( QStringLiteral( "read-only" ) ) );
  QVERIFY( file.setPermissions( QFileDevice::ReadOwner | QFileDevice::WriteOwner ) );
}

void TestMultiview::operatorEditSessionKeepsUndo()
{
  QString error;
  QgsVectorLayer *layer = mStore->layerFor( mSession->featureClasses().at( 0 ), &error );
  QVERIFY2( layer, qPrintable( error ) );
  QVERIFY( layer->startEditing() );
  QString id;
  QPointF left, right;
  Eigen::Vector3d truth;
  QVERIFY( goToStationWithPole( id, left, right, truth ) );
  mController->pick( 0, left );
  QVERIFY( mController->acceptPoint() );
  // in the edit buffer, not in the file; QGIS undo takes it back
  QCOMPARE( layer->editBuffer()->addedFeatures().size(), 1 );
  QCOMPARE( layer->dataProvider()->featureCount(), 0L );
  layer->undoStack()->undo();
  QCOMPARE( layer->editBuffer()->addedFeatures().size(), 0 );
  layer->undoStack()->redo();
  QCOMPARE( layer->editBuffer()->addedFeatures().size(), 1 );
  QVERIFY( layer->commitChanges() );
  QCOMPARE( layer->dataProvider()->featureCount(), 1L );
  QgsVectorLayer *vertices = mStore->verticesTable( &error );
  QVERIFY( vertices );
  QCOMPARE( vertices->featureCount(), 1L );
}

void TestMultiview::failedWriteKeepsTheFeatureInTheEditBuffer()
{
  // a pole layer made elsewhere with a mandatory field GeoStation does not fill: the write fails
  GDALDriverH driver = GDALGetDriverByName( "GPKG" );
  GDALDatasetH ds = GDALCreate( driver, measurementsPath().toUtf8().constData(), 0, 0, 0, GDT_Unknown, nullptr );
  QVERIFY( ds );
  OGRLayerH layer = GDALDatasetCreateLayer( ds, "pole", nullptr, wkbPoint25D, nullptr );
  for ( const QgsField &field : GeoStationMeasurementStore::featureFields( mSession->featureClasses().at( 0 ) ) )
  {
    OGRFieldDefnH defn = OGR_Fld_Create( field.name().toUtf8().constData(), field.type() == QVariant::String ? OFTString : field.type() == QVariant::Int ? OFTInteger : OFTReal );
    OGR_L_CreateField( layer, defn, TRUE );
    OGR_Fld_Destroy( defn );
  }
  OGRFieldDefnH inspector = OGR_Fld_Create( "inspector", OFTString );
  OGR_Fld_SetNullable( inspector, FALSE );
  OGR_L_CreateField( layer, inspector, TRUE );
  OGR_Fld_Destroy( inspector );
  GDALClose( ds );

  QString id;
  QPointF left, right;
  Eigen::Vector3d truth;
  QVERIFY( goToStationWithPole( id, left, right, truth ) );
  QSignalSpy messages( mController.get(), &GeoStationMeasurementController::message );
  mController->pick( 0, left );
  QVERIFY( mController->acceptPoint() );
  QVERIFY( messages.last().at( 1 ).toBool() ); // a warning
  QVERIFY2( messages.last().at( 0 ).toString().contains( QStringLiteral( "edit buffer" ) ), qPrintable( messages.last().at( 0 ).toString() ) );
  QgsVectorLayer *pole = mStore->measurementLayers().value( 0 );
  QVERIFY( pole && pole->isEditable() );
  QCOMPARE( pole->editBuffer()->addedFeatures().size(), 1 );
  // the operator fills the field and saves: feature and vertex rows are written
  const QgsFeatureId fid = pole->editBuffer()->addedFeatures().firstKey();
  QVERIFY( pole->changeAttributeValue( fid, pole->fields().indexFromName( QStringLiteral( "inspector" ) ), QStringLiteral( "K. Kraus" ) ) );
  QVERIFY2( pole->commitChanges(), qPrintable( pole->commitErrors().join( '\n' ) ) );
  QCOMPARE( pole->dataProvider()->featureCount(), 1L );
  QString error;
  QCOMPARE( mStore->verticesTable( &error )->featureCount(), 1L );
}

void TestMultiview::removedGeoPackageLosesNothing()
{
  QVERIFY( measurePoleFrom( 0 ) );
  QgsVectorLayer *pole = mStore->measurementLayers().value( 0 );
  QVERIFY( pole );
  QCOMPARE( pole->dataProvider()->featureCount(), 1L );

  // the file moved away behind QGIS's back (a file manager, a sync client), then a pole measured
  const QString away = mDir.filePath( QStringLiteral( "moved-away.gpkg" ) );
  QFile::remove( away );
  QVERIFY( QFile::rename( measurementsPath(), away ) );
  QSignalSpy messages( mController.get(), &GeoStationMeasurementController::message );
  QVERIFY( measurePoleFrom( mSession->currentStation() + 1 ) );
  QVERIFY( messages.last().at( 1 ).toBool() ); // a warning
  QVERIFY2( messages.last().at( 0 ).toString().contains( QStringLiteral( "is no longer there" ) ), qPrintable( messages.last().at( 0 ).toString() ) );
  QVERIFY( pole->isEditable() );
  QCOMPARE( pole->editBuffer()->addedFeatures().size(), 1 );
  QVERIFY( !QFile::exists( measurementsPath() ) ); // no empty file left in its place

  // the next one joins it in the edit buffer, with the same warning
  QVERIFY( measurePoleFrom( mSession->currentStation() + 1 ) );
  QVERIFY2( messages.last().at( 0 ).toString().contains( QStringLiteral( "is no longer there" ) ), qPrintable( messages.last().at( 0 ).toString() ) );
  QCOMPARE( pole->editBuffer()->addedFeatures().size(), 2 );

  // Save Features As writes them, from the edit buffer, into a new file
  const QString saved = mDir.filePath( QStringLiteral( "saved-as.gpkg" ) );
  QgsVectorFileWriter::SaveVectorOptions options;
  options.driverName = QStringLiteral( "GPKG" );
  QString error;
  QCOMPARE( QgsVectorFileWriter::writeAsVectorFormatV3( pole, saved, QgsProject::instance()->transformContext(), options, &error ), QgsVectorFileWriter::NoError );
  GDALDatasetH written = GDALOpenEx( saved.toUtf8().constData(), GDAL_OF_VECTOR | GDAL_OF_READONLY, nullptr, nullptr, nullptr );
  QVERIFY( written );
  OGRLayerH layer = GDALDatasetGetLayer( written, 0 );
  QStringList ids;
  OGRFeatureH f;
  while ( ( f = OGR_L_GetNextFeature( layer ) ) )
  {
    ids << QString::fromUtf8( OGR_F_GetFieldAsString( f, OGR_F_GetFieldIndex( f, "measurement_id" ) ) );
    OGR_F_Destroy( f );
  }
  GDALClose( written );
  for ( const QgsFeature &buffered : pole->editBuffer()->addedFeatures() )
    QVERIFY2( ids.contains( buffered.attribute( QStringLiteral( "measurement_id" ) ).toString() ), qPrintable( ids.join( ' ' ) ) );
  pole->rollBack();
}

void TestMultiview::fullDiskKeepsTheFeatureUntilThereIsRoom()
{
  QVERIFY( measurePoleFrom( 0 ) );
  QgsVectorLayer *pole = mStore->measurementLayers().value( 0 );
  QVERIFY( pole );
  QCOMPARE( pole->dataProvider()->featureCount(), 1L );

  QSignalSpy messages( mController.get(), &GeoStationMeasurementController::message );
  QVERIFY( measurePoleWithDiskFull( mSession->currentStation() + 1 ) );
  QVERIFY( messages.last().at( 1 ).toBool() ); // a warning
  QVERIFY2( messages.last().at( 0 ).toString().contains( QStringLiteral( "stays in the layer's edit buffer" ) ), qPrintable( messages.last().at( 0 ).toString() ) );
  QVERIFY( pole->isEditable() );
  QCOMPARE( pole->editBuffer()->addedFeatures().size(), 1 );

  // room again: saving the edits writes the feature and its vertex row
  QVERIFY2( pole->commitChanges(), qPrintable( pole->commitErrors().join( '\n' ) ) );
  GDALDatasetH written = GDALOpenEx( measurementsPath().toUtf8().constData(), GDAL_OF_VECTOR | GDAL_OF_READONLY, nullptr, nullptr, nullptr );
  QVERIFY( written );
  QCOMPARE( OGR_L_GetFeatureCount( GDALDatasetGetLayerByName( written, "pole" ), TRUE ), 2LL );
  GDALClose( written );
  QString error;
  QgsVectorLayer *vertices = mStore->verticesTable( &error );
  QVERIFY2( vertices, qPrintable( error ) );
  QCOMPARE( vertices->featureCount(), 2L );
}

void TestMultiview::pluginUnloadedWithEditsPendingKeepsTheirVertices()
{
  QVERIFY( measurePoleFrom( 0 ) );
  QgsVectorLayer *pole = mStore->measurementLayers().value( 0 );
  QVERIFY( pole );
  // the second pole cannot be written (the disk full): it stays in the edit buffer, its vertex rows wait for its fid
  QVERIFY( measurePoleWithDiskFull( mSession->currentStation() + 1 ) );
  QCOMPARE( pole->editBuffer()->addedFeatures().size(), 1 );
  const QString pending = pole->editBuffer()->addedFeatures().begin()->attribute( QStringLiteral( "measurement_id" ) ).toString();
  QVERIFY( !pending.isEmpty() );

  // the plugin goes away (unloaded, or QGIS closing) with the feature still unsaved: its vertex rows are written now,
  // linked by measurement_id
  mController.reset();
  mStore.reset();
  const auto vertexRows = [this]( const QString &measurementId, bool *fidNull )
  {
    GDALDatasetH ds = GDALOpenEx( measurementsPath().toUtf8().constData(), GDAL_OF_VECTOR | GDAL_OF_READONLY, nullptr, nullptr, nullptr );
    int rows = 0;
    if ( OGRLayerH table = ds ? GDALDatasetGetLayerByName( ds, "vertices" ) : nullptr )
    {
      OGR_L_SetAttributeFilter( table, QStringLiteral( "measurement_id = '%1'" ).arg( measurementId ).toUtf8().constData() );
      while ( OGRFeatureH f = OGR_L_GetNextFeature( table ) )
      {
        ++rows;
        *fidNull = !OGR_F_IsFieldSetAndNotNull( f, OGR_F_GetFieldIndex( f, "feature_fid" ) );
        OGR_F_Destroy( f );
      }
    }
    if ( ds )
      GDALClose( ds );
    return rows;
  };
  bool fidNull = false;
  QCOMPARE( vertexRows( pending, &fidNull ), 1 );
  QVERIFY( fidNull );

  // saved later through QGIS: the feature and its vertices are both in the file, joined by measurement_id
  QVERIFY2( pole->commitChanges(), qPrintable( pole->commitErrors().join( '\n' ) ) );
  GDALDatasetH written = GDALOpenEx( measurementsPath().toUtf8().constData(), GDAL_OF_VECTOR | GDAL_OF_READONLY, nullptr, nullptr, nullptr );
  QVERIFY( written );
  OGRLayerH poles = GDALDatasetGetLayerByName( written, "pole" );
  OGR_L_SetAttributeFilter( poles, QStringLiteral( "measurement_id = '%1'" ).arg( pending ).toUtf8().constData() );
  QCOMPARE( OGR_L_GetFeatureCount( poles, TRUE ), 1LL );
  GDALClose( written );
  QCOMPARE( vertexRows( pending, &fidNull ), 1 );

  // a feature the operator discarded (edits rolled back) gets no rows
  mStore = std::make_unique<GeoStationMeasurementStore>( mSession.get(), QgsProject::instance() );
  mController = std::make_unique<GeoStationMeasurementController>( mSession.get(), mStore.get() );
  QVERIFY( measurePoleWithDiskFull( mSession->currentStation() + 1 ) );
  QCOMPARE( pole->editBuffer()->addedFeatures().size(), 1 );
  const QString discarded = pole->editBuffer()->addedFeatures().begin()->attribute( QStringLiteral( "measurement_id" ) ).toString();
  QVERIFY( pole->rollBack() );
  mController.reset();
  mStore.reset();
  QCOMPARE( vertexRows( discarded, &fidNull ), 0 );
}

void TestMultiview::imageDeletedWhileItsViewIsOpen()
{
  QString id;
  QPointF left, right;
  Eigen::Vector3d truth;
  QVERIFY( goToStationWithPole( id, left, right, truth ) );
  // the partner view's image file deleted (moved away) after the views opened, before it was read for matching
  const QString partner = mSession->imagePath( mSession->viewImages().at( 1 ) );
  const QString away = partner + QStringLiteral( ".away" );
  QVERIFY( QFile::rename( partner, away ) );
  QSignalSpy messages( mController.get(), &GeoStationMeasurementController::message );
  mController->pick( 0, left );
  QVERIFY( mController->hasOpenPoint() ); // the click itself stands
  QCOMPARE( messages.count(), 1 );
  QVERIFY( messages.at( 0 ).at( 1 ).toBool() );
  QVERIFY2( messages.at( 0 ).at( 0 ).toString().contains( QStringLiteral( "The image of view 2 (%1) cannot be read" ).arg( mSession->viewImages().at( 1 ) ) ),
            qPrintable( messages.at( 0 ).at( 0 ).toString() ) );
  QVERIFY( !mController->viewStates()[1].proposed );
  QVERIFY2( mController->viewStates()[1].status.contains( QStringLiteral( "its image cannot be read" ) ), qPrintable( mController->viewStates()[1].status ) );

  // the operator measures the point there by hand: the vertex and the feature are made as ever
  mController->pick( 1, right );
  QVERIFY( mController->acceptPoint() );
  QgsVectorLayer *pole = mStore->measurementLayers().value( 0 );
  QVERIFY( pole );
  QCOMPARE( pole->dataProvider()->featureCount(), 1L );

  // the file put back: the next click matches in it again
  QVERIFY( QFile::rename( away, partner ) );
  mController->pick( 0, left );
  QVERIFY2( mController->viewStates()[1].proposed, qPrintable( mController->viewStates()[1].status ) );
  QVERIFY( QLineF( mController->viewStates()[1].pixel, right ).length() < 1.0 );
  mController->cancel();
}

void TestMultiview::blockFileChangedOnDiskIsReadAgain()
{
  QFile original( mBlockPath );
  QVERIFY( original.open( QIODevice::ReadOnly ) );
  const QByteArray originalText = original.readAll();
  original.close();
  mSession->setCurrentStation( 3 );
  const QStringList images = mSession->viewImages();
  const Eigen::Vector3d centre = mSession->orientedImage( images.at( 0 ) )->exterior().projectionCentre;
  QSignalSpy reloaded( mSession.get(), &GeoStationMultiviewSession::blockReloaded );
  QSignalSpy problems( mSession.get(), &GeoStationMultiviewSession::blockFileProblem );

  // a bundle adjustment writes the block again (atomically: a temporary file renamed into place), one image moved by 0.5 m
  geostation::Block block = geostation::Block::load( mBlockPath.toStdString() );
  for ( geostation::BlockImage &image : block.images )
    if ( image.id == images.at( 0 ).toStdString() )
      image.exterior->projectionCentre.x() += 0.5;
  block.save( mBlockPath.toStdString() );
  QVERIFY( reloaded.wait( 5000 ) );
  QVERIFY2( reloaded.last().at( 0 ).toString().contains( QStringLiteral( "1 image(s) have another orientation" ) ), qPrintable( reloaded.last().at( 0 ).toString() ) );
  QCOMPARE( mSession->currentStation(), 3 ); // the operator stays where they were
  QCOMPARE( mSession->viewImages(), images );
  QCOMPARE( mSession->orientedImage( images.at( 0 ) )->exterior().projectionCentre.x(), centre.x() + 0.5 );

  // a writer that leaves it broken (half written): one sentence, and the block as loaded stays
  {
    QFile broken( mBlockPath );
    QVERIFY( broken.open( QIODevice::WriteOnly | QIODevice::Truncate ) );
    broken.write( originalText.left( originalText.size() / 2 ) );
  }
  QVERIFY( problems.wait( 5000 ) );
  QVERIFY2( problems.last().at( 0 ).toString().contains( QStringLiteral( "cannot be read now" ) ), qPrintable( problems.last().at( 0 ).toString() ) );
  QCOMPARE( mSession->orientedImage( images.at( 0 ) )->exterior().projectionCentre.x(), centre.x() + 0.5 );

  // the file as it was: read again
  {
    QFile restored( mBlockPath );
    QVERIFY( restored.open( QIODevice::WriteOnly | QIODevice::Truncate ) );
    restored.write( originalText );
  }
  QVERIFY( reloaded.wait( 5000 ) );
  QCOMPARE( mSession->orientedImage( images.at( 0 ) )->exterior().projectionCentre.x(), centre.x() );
}

void TestMultiview::viewsShowPlaceholdersEnhancementsAndFeatures()
{
  // a missing image: its view says so, the others work
  const QString missing = mDir.filePath( QStringLiteral( "run/images/S0003_SR.tif" ) );
  QVERIFY( QFile::rename( missing, missing + ".away" ) );
  GeoStationMultiviewDock dock( mSession.get(), mController.get(), mStore.get() );
  dock.resize( 1200, 800 );
  dock.show();
  QCOMPARE( dock.viewCount(), 3 );
  mSession->setCurrentStation( 2 );
  QVERIFY( dock.view( 0 )->hasImage() );
  QVERIFY( dock.view( 1 )->hasImage() );
  QVERIFY( !dock.view( 2 )->hasImage() );
  QVERIFY2( dock.view( 2 )->placeholderText().contains( QStringLiteral( "does not exist" ) ), qPrintable( dock.view( 2 )->placeholderText() ) );
  QVERIFY( QFile::rename( missing + ".away", missing ) );
  // an image that fails to decode
  const QString broken = mDir.filePath( QStringLiteral( "run/images/S0004_FR.tif" ) );
  QVERIFY( QFile::copy( broken, broken + ".good" ) );
  {
    QFile f( broken );
    QVERIFY( f.open( QIODevice::WriteOnly ) );
    f.write( "not a tiff at all" );
  }
  mSession->setCurrentStation( 3 );
  QVERIFY( !dock.view( 1 )->hasImage() );
  QVERIFY2( dock.view( 1 )->placeholderText().contains( QStringLiteral( "cannot" ) ), qPrintable( dock.view( 1 )->placeholderText() ) );
  QVERIFY( dock.view( 0 )->hasImage() );
  QFile::remove( broken );
  QVERIFY( QFile::rename( broken + ".good", broken ) );

  // enhancement in memory, file untouched
  const QString path = mDir.filePath( QStringLiteral( "run/images/S0004_FL.tif" ) );
  const QDateTime modified = QFileInfo( path ).lastModified();
  dock.setViewEnhancement( 0, QStringLiteral( "equalise" ) );
  QCOMPARE( dock.view( 0 )->enhancement(), QStringLiteral( "equalise" ) );
  QVERIFY( dock.view( 0 )->canvas()->layers().value( 0 )->source().startsWith( QLatin1String( "/vsimem/" ) ) );
  QCOMPARE( QFileInfo( path ).lastModified(), modified );
  dock.setViewEnhancement( 0, QString() );
  QCOMPARE( dock.view( 0 )->canvas()->layers().value( 0 )->source(), path );
  QCOMPARE( dock.view( 0 )->valueAt( QPointF( 10.5, 10.5 ) ).isEmpty(), false );
  QCOMPARE( dock.view( 0 )->valueAt( QPointF( -1, 10 ) ), QString() );

  // a measured feature is drawn into the views; deleting it removes it
  QString id;
  QPointF left, right;
  Eigen::Vector3d truth;
  QVERIFY( goToStationWithPole( id, left, right, truth ) );
  QCOMPARE( dock.view( 0 )->featureOverlayCount(), 0 );
  mController->pick( 0, left );
  QVERIFY( mController->acceptPoint() );
  QTRY_COMPARE( dock.view( 0 )->featureOverlayCount(), 1 );
  QTRY_COMPARE( dock.view( 1 )->featureOverlayCount(), 1 );
  QgsVectorLayer *layer = mStore->measurementLayers().value( 0 );
  QVERIFY( layer->startEditing() );
  QgsFeature f;
  layer->getFeatures().nextFeature( f );
  QVERIFY( layer->deleteFeature( f.id() ) );
  QTRY_COMPARE( dock.view( 0 )->featureOverlayCount(), 0 );
  layer->rollBack();
  QTRY_COMPARE( dock.view( 0 )->featureOverlayCount(), 1 );
  QVERIFY( dock.messagesText().contains( QStringLiteral( "intersection" ) ) );
  QVERIFY( dock.lastNavigationMs() >= 0 );
}

void TestMultiview::navigationPreparesTheStationAndTheNextForMatching()
{
  GeoStationMultiviewDock dock( mSession.get(), mController.get(), mStore.get() );
  dock.resize( 900, 600 );
  dock.show();
  // stepping on faster than the images load: what the stations passed asked for and was not started is dropped
  for ( int station = 0; station < 5; ++station )
    mSession->setCurrentStation( station );
  // the station shown (S0005) and the next (S0006) are ready for the operator's first click, read by a thread
  // of the core's ImagePrefetcher (its threading is tested under ThreadSanitizer there)
  for ( const QString id : { "S0005_FL", "S0005_FR", "S0005_SR", "S0006_FL", "S0006_FR", "S0006_SR" } )
    QTRY_VERIFY2_WITH_TIMEOUT( mController->imageCache().contains( mSession->imagePath( id ).toStdString() ), qPrintable( id ), 20000 );
  const geostation::ImagePrefetcher::Summary summary = mController->prefetchSummary();
  QVERIFY2( summary.requested >= 6 && summary.failed == 0, qPrintable( QStringLiteral( "%1 requested, %2 failed" ).arg( summary.requested ).arg( summary.failed ) ) );
  QCOMPARE( summary.loaded + summary.superseded, summary.requested );
  // a station whose images are ready asks for nothing of them again
  const size_t before = summary.requested;
  mSession->setCurrentStation( 4 );
  QCOMPARE( mController->prefetchSummary().requested, before );
  // loads left pending: the next test's init() deletes the controller, which waits for the one in progress only
  mSession->setCurrentStation( 8 );
}

void TestMultiview::photosAreShownInTheirPixelsTurnedAsTagged()
{
  // a phone photo held upright: stored 64 x 48 pixels, tagged to be shown turned 90 degrees clockwise (EXIF
  // orientation 6); the view turns it, the pixels measured stay the stored ones
  const auto writePhoto = [this]( const QString &name, const char *tag ) {
    const QString path = mDir.filePath( name );
    GDALDatasetH memory = GDALCreate( GDALGetDriverByName( "MEM" ), "", 64, 48, 1, GDT_Byte, nullptr );
    std::vector<unsigned char> pixels( 64 * 48 );
    for ( size_t i = 0; i < pixels.size(); ++i )
      pixels[i] = static_cast<unsigned char>( 40 + ( i % 64 ) * 2 + i / 64 ); // 40 + 2 col + row
    if ( GDALRasterIO( GDALGetRasterBand( memory, 1 ), GF_Write, 0, 0, 64, 48, pixels.data(), 64, 48, GDT_Byte, 0, 0 ) != CE_None )
      qWarning() << "cannot write the test photo";
    if ( tag )
      GDALSetMetadataItem( memory, "EXIF_Orientation", tag, nullptr );
    GDALClose( GDALCreateCopy( GDALGetDriverByName( "JPEG" ), path.toUtf8().constData(), memory, FALSE, nullptr, nullptr, nullptr ) );
    GDALClose( memory );
    return path;
  };
  GeoStationImageView view( 0 );
  view.resize( 400, 460 );
  view.show();
  view.showImage( QStringLiteral( "upright" ), writePhoto( QStringLiteral( "upright.jpg" ), "6" ), 64, 48 );
  QVERIFY( view.hasImage() );
  QCOMPARE( view.viewTurnDeg(), 90 );
  QCOMPARE( view.canvas()->rotation(), 90.0 );
  const QgsMapToPixel &toScreen = view.canvas()->mapSettings().mapToPixel();
  const auto onScreen = [&]( double col, double row ) { return toScreen.transform( GeoStationImagePointTool::mapFromPixel( col, row ) ); };
  const QgsPointXY topLeft = onScreen( 0, 0 ), topRight = onScreen( 64, 0 ), bottomLeft = onScreen( 0, 48 ), bottomRight = onScreen( 64, 48 );
  // the stored top row runs down the right side of the view, from its top
  QVERIFY2( std::abs( topLeft.x() - topRight.x() ) < 0.5 && topRight.y() > topLeft.y() + 100, qPrintable( QStringLiteral( "%1 %2 / %3 %4" ).arg( topLeft.x() ).arg( topLeft.y() ).arg( topRight.x() ).arg( topRight.y() ) ) );
  QVERIFY( topLeft.x() > bottomLeft.x() + 100 && std::abs( topLeft.y() - bottomLeft.y() ) < 0.5 );
  // the whole photo in the view
  const QSize size = view.canvas()->mapSettings().outputSize();
  for ( const QgsPointXY &corner : { topLeft, topRight, bottomLeft, bottomRight } )
    QVERIFY2( corner.x() > -1 && corner.y() > -1 && corner.x() < size.width() + 1 && corner.y() < size.height() + 1,
              qPrintable( QStringLiteral( "%1 %2 in %3 x %4" ).arg( corner.x() ).arg( corner.y() ).arg( size.width() ).arg( size.height() ) ) );
  // a click on the view is measured in the stored pixels
  const QPointF clicked = GeoStationImagePointTool::pixelFromMap( view.canvas()->getCoordinateTransform()->toMapCoordinates( QPoint( qRound( onScreen( 10, 20 ).x() ), qRound( onScreen( 10, 20 ).y() ) ) ) );
  QVERIFY2( std::abs( clicked.x() - 10 ) < 0.5 && std::abs( clicked.y() - 20 ) < 0.5, qPrintable( QStringLiteral( "%1 %2" ).arg( clicked.x() ).arg( clicked.y() ) ) );
  // a photo without the tag: as stored
  view.showImage( QStringLiteral( "plain" ), writePhoto( QStringLiteral( "plain.jpg" ), nullptr ), 64, 48 );
  QCOMPARE( view.viewTurnDeg(), 0 );
  QVERIFY( !view.viewMirrored() );
  QCOMPARE( view.canvas()->rotation(), 0.0 );
  QVERIFY( view.canvas()->mapSettings().mapToPixel().transform( GeoStationImagePointTool::mapFromPixel( 0, 0 ) ).x() <
           view.canvas()->mapSettings().mapToPixel().transform( GeoStationImagePointTool::mapFromPixel( 64, 0 ) ).x() );
  // photos tagged to be shown mirrored: 2 (left to right) and 5 (the stored rows as the view's columns, a
  // transpose: mirrored, then turned 270 degrees). What is drawn on the screen at a stored pixel is that pixel's
  // value, and a click there is measured at that pixel as stored
  const auto screenOf = [&view]( double col, double row ) {
    return view.canvas()->mapSettings().mapToPixel().transform( view.mapFromPixel( QPointF( col, row ) ) );
  };
  const auto checkShownAndClicked = [&]( const QString &name ) {
    view.canvas()->refresh();
    view.canvas()->waitWhileRendering();
    QCoreApplication::processEvents();
    const QImage screen = view.canvas()->grab().toImage();
    auto *tool = qobject_cast<GeoStationImagePointTool *>( view.canvas()->mapTool() );
    QVERIFY( tool );
    QSignalSpy picked( tool, &GeoStationImagePointTool::pixelPicked );
    // QGIS draws a grey band stretched between its 2 and 98 % values: what is shown is a rising linear
    // function of the stored value wherever the view shows the right pixel
    const QVector<QPoint> samples { { 5, 5 }, { 58, 8 }, { 10, 40 }, { 50, 30 }, { 30, 20 }, { 20, 10 }, { 45, 44 }, { 2, 30 } };
    QVector<double> shown, truth;
    for ( const QPoint &stored : samples )
    {
      const QgsPointXY at = screenOf( stored.x() + 0.5, stored.y() + 0.5 );
      shown << qGray( screen.pixel( qRound( at.x() - 0.5 ), qRound( at.y() - 0.5 ) ) );
      truth << 40 + 2 * stored.x() + stored.y();
      const QPoint onScreen( qRound( at.x() ), qRound( at.y() ) );
      QgsMapMouseEvent press( view.canvas(), QEvent::MouseButtonPress, onScreen, Qt::LeftButton, Qt::LeftButton );
      tool->canvasPressEvent( &press );
      QgsMapMouseEvent release( view.canvas(), QEvent::MouseButtonRelease, onScreen, Qt::LeftButton, Qt::NoButton );
      tool->canvasReleaseEvent( &release );
      QVERIFY( !picked.isEmpty() );
      const QPointF clickedPixel = picked.takeLast().at( 0 ).toPointF();
      QVERIFY2( std::abs( clickedPixel.x() - stored.x() - 0.5 ) < 1.0 && std::abs( clickedPixel.y() - stored.y() - 0.5 ) < 1.0,
                qPrintable( QStringLiteral( "%1: clicked at %2 %3 for %4 %5" ).arg( name ).arg( clickedPixel.x() ).arg( clickedPixel.y() ).arg( stored.x() ).arg( stored.y() ) ) );
    }
    double mt = 0, ms = 0;
    for ( int i = 0; i < samples.size(); ++i )
    {
      mt += truth[i] / samples.size();
      ms += shown[i] / samples.size();
    }
    double stt = 0, sts = 0;
    for ( int i = 0; i < samples.size(); ++i )
    {
      stt += ( truth[i] - mt ) * ( truth[i] - mt );
      sts += ( truth[i] - mt ) * ( shown[i] - ms );
    }
    const double gain = sts / stt;
    double worst = 0;
    for ( int i = 0; i < samples.size(); ++i )
      worst = std::max( worst, std::abs( ms + gain * ( truth[i] - mt ) - shown[i] ) );
    QVERIFY2( gain > 0.5 && worst < 10, qPrintable( QStringLiteral( "%1: shown = %2 x stored + c, worst residual %3 grey levels" ).arg( name ).arg( gain ).arg( worst ) ) );
    // and through the layer's own sampling (to the JPEG's error)
    QVERIFY2( std::abs( view.valueAt( QPointF( 10.5, 20.5 ) ).toInt() - ( 40 + 20 + 20 ) ) <= 3, qPrintable( view.valueAt( QPointF( 10.5, 20.5 ) ) ) );
  };
  view.showImage( QStringLiteral( "mirrored" ), writePhoto( QStringLiteral( "mirrored.jpg" ), "2" ), 64, 48 );
  QVERIFY( view.viewMirrored() );
  QCOMPARE( view.viewTurnDeg(), 0 );
  QVERIFY( screenOf( 0, 0 ).x() > screenOf( 64, 0 ).x() + 100 && std::abs( screenOf( 0, 0 ).y() - screenOf( 64, 0 ).y() ) < 0.5 ); // the top row right to left
  QVERIFY( screenOf( 0, 48 ).y() > screenOf( 0, 0 ).y() + 100 );
  checkShownAndClicked( QStringLiteral( "mirrored" ) );
  view.showImage( QStringLiteral( "transposed" ), writePhoto( QStringLiteral( "transposed.jpg" ), "5" ), 64, 48 );
  QVERIFY( view.viewMirrored() );
  QCOMPARE( view.viewTurnDeg(), 270 );
  // the stored top row down the left side from the top, the stored left column along the top from the left
  QVERIFY( std::abs( screenOf( 0, 0 ).x() - screenOf( 64, 0 ).x() ) < 0.5 && screenOf( 64, 0 ).y() > screenOf( 0, 0 ).y() + 100 );
  QVERIFY( std::abs( screenOf( 0, 0 ).y() - screenOf( 0, 48 ).y() ) < 0.5 && screenOf( 0, 48 ).x() > screenOf( 0, 0 ).x() + 100 );
  QVERIFY( screenOf( 0, 0 ).x() < screenOf( 64, 48 ).x() && screenOf( 0, 0 ).y() < screenOf( 64, 48 ).y() );
  checkShownAndClicked( QStringLiteral( "transposed" ) );
  // an overlay drawn in the stored pixels lands on them
  QVERIFY( view.inView( QgsGeometry::fromPointXY( QgsPointXY( 10, -20 ) ) ).asPoint() == view.mapFromPixel( QPointF( 10, 20 ) ) );
  view.showImage( QStringLiteral( "upside_down" ), writePhoto( QStringLiteral( "upside_down.jpg" ), "3" ), 64, 48 );
  QCOMPARE( view.canvas()->rotation(), 180.0 );

  // a scanned photo archived with a world file: drawn in its pixels all the same, where the overlays and clicks are
  const QString scan = writePhoto( QStringLiteral( "scan.jpg" ), nullptr );
  {
    QFile world( mDir.filePath( QStringLiteral( "scan.wld" ) ) );
    QVERIFY( world.open( QIODevice::WriteOnly ) );
    world.write( "0.5\n0\n0\n-0.5\n500000.25\n5200000.25\n" );
  }
  view.showImage( QStringLiteral( "scan" ), scan, 64, 48 );
  QVERIFY( view.hasImage() );
  QgsRasterLayer *shown = qobject_cast<QgsRasterLayer *>( view.canvas()->layers().value( 0 ) );
  QVERIFY( shown );
  QCOMPARE( shown->extent(), QgsRectangle( 0, -48, 64, 0 ) );
  QVERIFY( shown->source().startsWith( QLatin1String( "/vsimem/" ) ) );
  QVERIFY( !view.valueAt( QPointF( 10.5, 20.5 ) ).isEmpty() );
  QVERIFY( view.canvas()->mapSettings().visibleExtent().contains( QgsPointXY( 32, -24 ) ) );
}

void TestMultiview::exportWritesShapefileAndDxfWithAttributesAndZ()
{
  // a pole and a kerb line
  QString id;
  QPointF left, right;
  Eigen::Vector3d truth;
  QVERIFY( goToStationWithPole( id, left, right, truth ) );
  mController->pick( 0, left );
  QVERIFY( mController->acceptPoint() );
  mSession->setCurrentClass( QStringLiteral( "Kerb line" ) );
  for ( const QPointF &pixel : { QPointF( 200, 400 ), QPointF( 400, 440 ) } )
  {
    mController->pick( 2, pixel );
    QVERIFY( mController->acceptPoint() );
  }
  QVERIFY( mController->finishFeature() );
  QString error;
  QgsVectorLayer *pole = mStore->layerFor( mSession->featureClasses().at( 0 ), &error );
  QVERIFY( pole );
  QgsFeature measured;
  QVERIFY( pole->getFeatures().nextFeature( measured ) );
  const QgsGeometry measuredGeometry = measured.geometry();
  const QgsPoint *p = qgsgeometry_cast<const QgsPoint *>( measuredGeometry.constGet() );
  QVERIFY( p );

  std::unique_ptr<QgsProcessingAlgorithm> created( GeoStationProcessing::ExportMeasurementsAlgorithm().create() );
  QgsProcessingAlgorithm &algorithm = *created;
  QgsProcessingContext context;
  QgsProcessingFeedback feedback;
  const QString folder = mDir.filePath( QStringLiteral( "export" ) );
  QVariantMap parameters { { QStringLiteral( "INPUT" ), measurementsPath() }, { QStringLiteral( "OUTPUT_FOLDER" ), folder } };
  bool ok = false;
  const QVariantMap results = algorithm.run( parameters, context, &feedback, &ok );
  QVERIFY( ok );
  QCOMPARE( results.value( QStringLiteral( "LAYERS" ) ).toInt(), 2 );
  QCOMPARE( results.value( QStringLiteral( "FEATURES" ) ).toInt(), 2 );

  // Shapefile: attributes and Z
  QgsVectorLayer shp( QDir( folder ).filePath( QStringLiteral( "pole.shp" ) ), QStringLiteral( "pole" ), QStringLiteral( "ogr" ) );
  QVERIFY( shp.isValid() );
  QVERIFY( QgsWkbTypes::hasZ( shp.wkbType() ) );
  QgsFeature f;
  QVERIFY( shp.getFeatures().nextFeature( f ) );
  const QgsGeometry shpGeometry = f.geometry();
  const QgsPoint *q = qgsgeometry_cast<const QgsPoint *>( shpGeometry.constGet() );
  QVERIFY( q );
  QCOMPARE( q->z(), p->z() );
  QCOMPARE( f.attribute( "class" ).toString(), QStringLiteral( "Pole" ) );
  QCOMPARE( f.attribute( "kind" ).toString(), QStringLiteral( "pole" ) );
  QCOMPARE( f.attribute( "sigma_x" ).toDouble(), measured.attribute( "sigma_x" ).toDouble() );
  QCOMPARE( f.attribute( "measuremen" ).toString(), measured.attribute( "measurement_id" ).toString() );
  QgsVectorLayer kerbShp( QDir( folder ).filePath( QStringLiteral( "kerb_line.shp" ) ), QStringLiteral( "kerb" ), QStringLiteral( "ogr" ) );
  QVERIFY( kerbShp.isValid() && QgsWkbTypes::hasZ( kerbShp.wkbType() ) );
  QCOMPARE( kerbShp.featureCount(), 1L );

  // DXF: 3D geometry on the class's layer, attributes through the entity handle
  QgsVectorLayer dxf( QDir( folder ).filePath( QStringLiteral( "pole.dxf" ) ), QStringLiteral( "pole" ), QStringLiteral( "ogr" ) );
  QVERIFY( dxf.isValid() );
  QVERIFY( dxf.getFeatures().nextFeature( f ) );
  QCOMPARE( f.attribute( "Layer" ).toString(), QStringLiteral( "pole" ) );
  const QgsGeometry dxfGeometry = f.geometry();
  const QgsPoint *d = qgsgeometry_cast<const QgsPoint *>( dxfGeometry.constGet() );
  QVERIFY( d && d->is3D() );
  QVERIFY( std::abs( d->z() - p->z() ) < 1e-6 );
  const QString handle = f.attribute( "EntityHandle" ).toString();
  QFile csv( QDir( folder ).filePath( QStringLiteral( "pole_dxf_attributes.csv" ) ) );
  QVERIFY( csv.open( QIODevice::ReadOnly ) );
  const QStringList header = QString::fromUtf8( csv.readLine() ).trimmed().split( ',' );
  const QStringList row = QString::fromUtf8( csv.readLine() ).trimmed().split( ',' );
  QCOMPARE( row.at( header.indexOf( QStringLiteral( "EntityHandle" ) ) ), handle );
  QCOMPARE( row.at( header.indexOf( QStringLiteral( "measurement_id" ) ) ), measured.attribute( "measurement_id" ).toString() );
  QCOMPARE( row.at( header.indexOf( QStringLiteral( "class" ) ) ), QStringLiteral( "Pole" ) );
  QVERIFY( QFileInfo::exists( QDir( folder ).filePath( QStringLiteral( "vertices.csv" ) ) ) );
  QgsVectorLayer kerbDxf( QDir( folder ).filePath( QStringLiteral( "kerb_line.dxf" ) ), QStringLiteral( "kerb" ), QStringLiteral( "ogr" ) );
  QVERIFY( kerbDxf.getFeatures().nextFeature( f ) );
  QVERIFY( f.geometry().constGet()->is3D() );
  QCOMPARE( f.geometry().constGet()->nCoordinates(), 2 );

  // bad input: one sentence, nothing written
  const QString other = mDir.filePath( QStringLiteral( "export-bad" ) );
  parameters = { { QStringLiteral( "INPUT" ), mDir.filePath( QStringLiteral( "none.gpkg" ) ) }, { QStringLiteral( "OUTPUT_FOLDER" ), other } };
  algorithm.run( parameters, context, &feedback, &ok );
  QVERIFY( !ok );
  QVERIFY( !QFileInfo::exists( other ) || QDir( other ).entryList( QDir::NoDotAndDotDot | QDir::AllEntries | QDir::Hidden ).isEmpty() );
}

void TestMultiview::viewsMoveBetweenTheGridAndDocksOfTheirOwn()
{
  QMainWindow window;
  GeoStationMultiviewDock *dock = new GeoStationMultiviewDock( mSession.get(), mController.get(), mStore.get(), &window );
  window.addDockWidget( Qt::RightDockWidgetArea, dock );
  window.resize( 1400, 900 );
  window.show();
  QCOMPARE( window.findChildren<QgsDockWidget *>( QRegularExpression( QStringLiteral( "^GeoStationViewDock" ) ) ).size(), 0 );
  dock->setSeparateDocks( true );
  const QList<QgsDockWidget *> docks = window.findChildren<QgsDockWidget *>( QRegularExpression( QStringLiteral( "^GeoStationViewDock" ) ) );
  QCOMPARE( docks.size(), 3 );
  QVERIFY( qobject_cast<GeoStationImageView *>( docks.first()->widget() ) );
  // still working in their docks: the next station shows in every view
  mSession->stepStation( 1 );
  QCOMPARE( dock->view( 1 )->imageId(), mSession->viewImages().at( 1 ) );
  QVERIFY( dock->view( 1 )->hasImage() );
  dock->setSeparateDocks( false );
  QTRY_COMPARE( window.findChildren<QgsDockWidget *>( QRegularExpression( QStringLiteral( "^GeoStationViewDock" ) ) ).size(), 0 );
  QVERIFY( dock->isAncestorOf( dock->view( 2 ) ) );
  QVERIFY( dock->view( 2 )->hasImage() );
}

void TestMultiview::overviewShowsRunStationsAndCones()
{
  QgsMapCanvas canvas;
  canvas.resize( 600, 400 );
  GeoStationOverviewLayers overview( mSession.get(), QgsProject::instance(), &canvas );
  overview.rebuild();
  QVERIFY( overview.stationsLayer() && overview.trajectoryLayer() && overview.conesLayer() );
  QCOMPARE( overview.stationsLayer()->featureCount(), 10L );
  QCOMPARE( overview.trajectoryLayer()->featureCount(), 1L );
  QCOMPARE( overview.conesLayer()->featureCount(), 3L );
  mSession->setCurrentStation( 6 );
  QgsFeature cone;
  overview.conesLayer()->getFeatures().nextFeature( cone );
  QCOMPARE( cone.attribute( "station" ).toString(), QStringLiteral( "S0007" ) );
  // the cone holds the station and opens away from it
  QVERIFY( cone.geometry().area() > 50 );
  // picking on the map: the nearest station
  const Eigen::Vector3d s3 = *mSession->run().at( 3 ).position;
  QCOMPARE( overview.stationNearestToMapPoint( QgsPointXY( s3.x() + 0.5, s3.y() - 0.5 ) ), 3 );
  overview.removeLayers();
  QVERIFY( !overview.stationsLayer() );
}

void TestMultiview::traceToolTracesStopsTakesBackAndWritesOneLine()
{
  QMainWindow window;
  GeoStationTraceController trace( mSession.get(), mStore.get() );
  GeoStationMultiviewDock *dock = new GeoStationMultiviewDock( mSession.get(), mController.get(), mStore.get(), &window, &trace );
  window.addDockWidget( Qt::RightDockWidgetArea, dock );
  window.resize( 1400, 900 );
  window.show();
  GeoStationOverviewLayers overview( mSession.get(), QgsProject::instance(), new QgsMapCanvas( &window ) );
  connect( &trace, &GeoStationTraceController::lineChanged, &overview, [&]
  {
    QVector<QgsPoint> points;
    for ( const Eigen::Vector3d &p : trace.line().points() )
      points << QgsPoint( p.x(), p.y(), p.z() );
    overview.setTracedLine( points );
  } );
  mSession->setCurrentStation( 0 );
  mSession->setCurrentClass( QStringLiteral( "Kerb line" ) );
  QAction *traceAction = dock->findChild<QAction *>( QStringLiteral( "mActionTrace" ) );
  QVERIFY( traceAction );
  traceAction->setChecked( true );

  // where the operator clicks: on the kerb face about 8 m ahead, well inside views 0 and 1
  const std::vector<geostation::TruthRoadLine> roads = geostation::readTruthRoadLines( mDir.filePath( QStringLiteral( "run/truth.gpkg" ) ).toStdString() );
  const std::vector<Eigen::Vector3d> truth = geostation::joinedTruthLine( roads, "R1-edge-right" );
  const geostation::OrientedImage *left = mSession->orientedImage( dock->view( 0 )->imageId() );
  const geostation::OrientedImage *right = mSession->orientedImage( dock->view( 1 )->imageId() );
  QVERIFY( left && right );
  const auto inside = []( const geostation::OrientedImage &image, const Eigen::Vector3d &p )
  {
    const geostation::GroundProjection g = image.projectGroundToPixel( p );
    return g.ok() && g.inFrame && ( g.pixelInImage.array() > 40.0 ).all() && g.pixelInImage.x() < image.camera().width - 40 && g.pixelInImage.y() < image.camera().height - 40;
  };
  std::optional<QPointF> click;
  for ( size_t i = 0; i + 1 < truth.size() && !click; ++i )
    for ( int k = 0; k < 10 && !click; ++k )
    {
      const Eigen::Vector3d p = truth[i] + k / 10.0 * ( truth[i + 1] - truth[i] );
      if ( ( p - left->exterior().projectionCentre ).head<2>().norm() >= 8.0 && inside( *left, p ) && inside( *right, p ) )
      {
        const Eigen::Vector2d px = left->projectGroundToPixel( p ).pixelInImage;
        click = QPointF( px.x() + 0.8, px.y() - 0.6 );
      }
    }
  QVERIFY2( click, "the kerb is not in view of the first station's two images" );

  // one click: the line grows station by station in every view and on the map
  QSignalSpy grown( &trace, &GeoStationTraceController::lineChanged );
  QSignalSpy stopped( &trace, &GeoStationTraceController::stopped );
  emit dock->view( 0 )->pixelPicked( 0, *click );
  QVERIFY( trace.isRunning() );
  QVERIFY( stopped.wait( 120000 ) );
  QVERIFY2( trace.line().vertices().size() >= 20, qPrintable( dock->messagesText() ) );
  const size_t stations = trace.line().stationIds().size();
  qInfo( "traced %zu stations, %zu vertices, %.1f m; stop %s: %s; last station on screen %.1f ms after it was traced", stations, trace.line().vertices().size(),
         trace.line().lengthM(), qPrintable( trace.lastStop() ), qPrintable( trace.lastStopMessage() ), trace.lastStationDelayMs() );
  QCOMPARE( trace.lastStop(), QStringLiteral( "end_of_run" ) );
  QVERIFY( stations >= 8 );
  QVERIFY( grown.count() >= static_cast<int>( stations ) );
  // every station reported in the messages as it was traced
  QVERIFY( dock->messagesText().count( QRegularExpression( QStringLiteral( "^Station S\\d+: " ), QRegularExpression::MultilineOption ) ) >= static_cast<int>( stations ) );
  QVERIFY( dock->view( 0 )->traceOverlayVertexCount() >= 2 );
  QVERIFY( dock->view( 1 )->traceOverlayVertexCount() >= 2 );
  QCOMPARE( overview.tracedLineVertexCount(), static_cast<int>( trace.line().vertices().size() ) );
  QVERIFY( dock->findChild<QLabel *>( QStringLiteral( "mTraceStatus" ) )->text().contains( QStringLiteral( "stations" ) ) );

  // Backspace takes back the last station's part
  const size_t before = trace.line().vertices().size();
  QTest::keyClick( dock->view( 0 )->canvas(), Qt::Key_Backspace );
  QCOMPARE( trace.line().stationIds().size(), stations - 1 );
  QVERIFY( trace.line().vertices().size() < before );

  // F writes one LineStringZ, method "traced", with its vertex rows; the views draw it back
  const std::vector<Eigen::Vector3d> written = trace.line().points();
  QTest::keyClick( dock->view( 0 )->canvas(), Qt::Key_F );
  QVERIFY( trace.line().empty() );
  QCOMPARE( overview.tracedLineVertexCount(), 0 );
  QString error;
  const GeoStationFeatureClass *kerb = mSession->findClass( QStringLiteral( "Kerb line" ) );
  QgsVectorLayer *layer = mStore->layerFor( *kerb, &error );
  QVERIFY2( layer, qPrintable( error ) );
  QCOMPARE( layer->featureCount(), 1L );
  QgsFeature f;
  QVERIFY( layer->getFeatures().nextFeature( f ) );
  QCOMPARE( f.attribute( "method" ).toString(), QStringLiteral( "traced" ) );
  QCOMPARE( f.geometry().constGet()->nCoordinates(), static_cast<int>( written.size() ) );
  QVERIFY( f.geometry().constGet()->is3D() );
  QVERIFY( f.attribute( "sigma_z" ).toDouble() > 0.0 );
  QgsVectorLayer *vertices = mStore->verticesTable( &error );
  QVERIFY( vertices );
  QgsFeatureRequest request;
  request.setFilterExpression( QStringLiteral( "measurement_id = '%1'" ).arg( f.attribute( "measurement_id" ).toString() ) );
  long rows = 0;
  QgsFeature row;
  for ( QgsFeatureIterator it = vertices->getFeatures( request ); it.nextFeature( row ); )
    ++rows;
  QCOMPARE( rows, static_cast<long>( written.size() ) );
  // on the kerb: the buffer method against the truth (0.10 m), the exact orientation
  const double from = geostation::projectOnto( truth, written.front(), true ).station, to = geostation::projectOnto( truth, written.back(), true ).station;
  const geostation::BufferScore score = geostation::bufferScore( written, geostation::polylineBetween( truth, from, to ), 0.10 );
  qInfo( "written line: completeness %.3f correctness %.3f", score.completeness, score.correctness );
  QVERIFY( score.completeness >= 0.95 );
  QVERIFY( score.correctness >= 0.98 );
  QTRY_VERIFY( dock->view( 0 )->featureOverlayCount() >= 1 );

  // Esc while tracing stops it after the station and keeps what was traced; Esc again drops the line
  emit dock->view( 0 )->pixelPicked( 0, *click );
  QVERIFY( trace.isRunning() );
  QTest::keyClick( dock->view( 0 )->canvas(), Qt::Key_Escape );
  QVERIFY( stopped.wait( 60000 ) );
  QCOMPARE( trace.lastStop(), QStringLiteral( "cancelled" ) );
  QVERIFY( !trace.line().empty() );
  QTest::keyClick( dock->view( 0 )->canvas(), Qt::Key_Escape );
  QVERIFY( trace.line().empty() );
  QCOMPARE( layer->featureCount(), 1L );

  // bad input: a click in the sky says why, traces nothing, writes nothing
  emit dock->view( 0 )->pixelPicked( 0, QPointF( 320.0, 20.0 ) );
  QVERIFY( stopped.wait( 60000 ) );
  QCOMPARE( trace.lastStop(), QStringLiteral( "no_edge" ) );
  QVERIFY( dock->messagesText().contains( QStringLiteral( "no edge or painted line within 8 px of the seed" ) ) );
  QVERIFY( trace.line().empty() );
  QVERIFY( !trace.finish() );
  QCOMPARE( layer->featureCount(), 1L );
  // a point class is no class to trace into
  mSession->setCurrentClass( QStringLiteral( "Pole" ) );
  QVERIFY( !trace.start( dock->view( 0 )->imageId(), *click ) );
  QVERIFY( dock->messagesText().contains( QStringLiteral( "Choose a line class" ) ) );
}

void TestMultiview::aReviewedChangeIsShownInTheImagesThatSeeIt()
{
  // a road "moved" 3 m: the map's course 2-D (no heights), the new course on the ground at a pole's foot
  GeoStationMultiviewDock dock( mSession.get(), mController.get(), mStore.get() );
  dock.resize( 1200, 800 );
  dock.show();
  mSession->setCurrentStation( mSession->run().size() - 1 ); // its cameras look on, away from the poles passed
  QStringList ids;
  for ( const geostation::BlockImage &image : mSession->block()->images )
    ids << QString::fromStdString( image.id );
  const auto oriented = [this]( const QString &id ) { return mSession->orientedImage( id ); };
  std::optional<Eigen::Vector3d> foot;
  for ( const auto &[pointId, point] : mTruth.objects )
  {
    const QStringList seeing = imagesSeeing( point, ids, oriented );
    bool shownNow = false;
    for ( const QString &id : mSession->viewImages() )
      shownNow = shownNow || seeing.contains( id );
    if ( pointId.rfind( "pole_", 0 ) == 0 && seeing.size() >= 2 && !shownNow )
    {
      foot = point;
      break;
    }
  }
  QVERIFY2( foot, "the run has a pole the last station does not see" );
  const double z = foot->z();
  const QgsGeometry newCourse( new QgsLineString( QVector<QgsPoint> { QgsPoint( foot->x() - 4, foot->y(), z ), QgsPoint( foot->x(), foot->y(), z ), QgsPoint( foot->x() + 4, foot->y(), z ) } ) );
  const QgsGeometry oldCourse( new QgsLineString( QVector<QgsPointXY> { QgsPointXY( foot->x() - 4, foot->y() + 3 ), QgsPointXY( foot->x() + 4, foot->y() + 3 ) } ) );
  dock.showChange( oldCourse, newCourse, mSession->crs() );

  // the views were given images that see it, and draw both courses there
  const QStringList seeing = imagesSeeing( *foot, ids, oriented );
  int drawn = 0;
  for ( int v = 0; v < dock.viewCount(); ++v )
  {
    const QString id = mSession->viewImages().value( v );
    if ( !seeing.contains( id ) || !dock.view( v )->hasImage() )
      continue;
    const QPair<int, int> counts = dock.view( v )->changeOverlayVertexCounts();
    QVERIFY2( counts.first >= 2 && counts.second >= 2, qPrintable( QStringLiteral( "%1: %2 old, %3 new vertices" ).arg( id ).arg( counts.first ).arg( counts.second ) ) );
    ++drawn;
  }
  QVERIFY2( drawn >= 2, qPrintable( QStringLiteral( "the change is drawn in %1 views" ).arg( drawn ) ) );

  // a road not found: only the old course; nothing selected: nothing drawn
  dock.showChange( oldCourse, QgsGeometry(), mSession->crs() );
  for ( int v = 0; v < dock.viewCount(); ++v )
    QCOMPARE( dock.view( v )->changeOverlayVertexCounts().second, 0 );
  dock.showChange( QgsGeometry(), QgsGeometry(), mSession->crs() );
  for ( int v = 0; v < dock.viewCount(); ++v )
    QCOMPARE( dock.view( v )->changeOverlayVertexCounts(), qMakePair( 0, 0 ) );
}

int main( int argc, char **argv )
{
  QgsApplication app( argc, argv, true );
  QgsApplication::init();
  QgsApplication::initQgis();
  int result = 0;
  {
    TestMultiview test;
    result = QTest::qExec( &test, argc, argv );
  }
  QgsApplication::exitQgis();
  return result;
}

#include "testmultiview.moc"

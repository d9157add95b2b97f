// The photo orientation dock without QGIS desktop (offscreen), on the
// simulator's scanned oblique photo added unoriented to a block (its inner
// orientation measured, as after Inner Orientation): control points loaded
// from the truth's control layer, four clicked in the Multiview's view of
// the photo (with 0.8 px of noise, an operator's click), the rest found semi-automatically and
// accepted, a blunder flagged and switched off, a ground click off the DEM
// refused, the orientation saved into the block and read back. Checked
// against the simulator's truth.
#include <random>

#include <Eigen/Geometry>
#include <Eigen/LU>

#include <QCheckBox>
#include <QComboBox>
#include <QDoubleSpinBox>
#include <QLineEdit>
#include <QPlainTextEdit>
#include <QJsonArray>
#include <QJsonDocument>
#include <QJsonObject>
#include <QItemSelectionModel>
#include <QLabel>
#include <QTableView>
#include <QTemporaryDir>
#include <QToolButton>
#include <QtTest/QtTest>

#include <gdal.h>

#include <qgsapplication.h>
#include <qgsfeatureiterator.h>
#include <qgsmapcanvas.h>
#include <qgsproject.h>
#include <qgsrasterlayer.h>
#include <qgsvectorlayer.h>

#include "controlpointmodel.h"
#include "featureclass.h"
#include "imageview.h"
#include "measurementcontroller.h"
#include "measurementstore.h"
#include "multiviewdock.h"
#include "multiviewsession.h"
#include "orientationdock.h"
#include "addphotodialog.h"
#include "layerinphoto.h"
#include "fiducialmodel.h"
#include "fiducialpanel.h"
#include "dem/demcoverage.h"
#include "geometry/crs.h"
#include "imageproc/fiducialdetection.h"
#include "io/block.h"
#include "simulation/surveysimulator.h"
#include "simulationtruth.h"

namespace
{
  //! Identify Automatically as the operator starts it (its button); waits for the background search; how many it offers.
  int identified( GeoStationOrientationDock &dock )
  {
    QToolButton *button = dock.findChild<QToolButton *>( QStringLiteral( "mIdentifyButton" ) );
    QSignalSpy finished( &dock, &GeoStationOrientationDock::identificationFinished );
    button->click();
    if ( finished.isEmpty() )
    {
      if ( button->text() != QStringLiteral( "Cancel Identification" ) ) // while it runs, the button stops it
        return -1;
      if ( !finished.wait( 120000 ) )
        return -1;
    }
    return button->text() == QStringLiteral( "Identify Automatically" ) ? finished.at( 0 ).at( 0 ).toInt() : -1;
  }
} // namespace

class TestOrientationDock : public QObject
{
    Q_OBJECT

  private slots:
    void initTestCase();
    void cleanupTestCase();
    void clickedAndFoundControlOrientTheScannedPhoto();
    void addPhotoStartsABlockAndOpensThePhotoUnoriented();

  private:
    //! The true pixel of a control point in the scan, or nothing when it does not show.
    std::optional<QPointF> truePixel( const std::string &id ) const;

    QTemporaryDir mDir;
    QString mBlockPath;
    geostation::TruthTable mTruth;
    std::unique_ptr<geostation::Block> mTruthBlock;
};

void TestOrientationDock::initTestCase()
{
  QVERIFY( mDir.isValid() );
  geostation::SimulationOptions options;
  options.preset = geostation::SurveyPreset::ObliquePhoto;
  options.seed = 5;
  options.scannedFilm = true;
  options.degradation.noiseSigma = 2.0;
  options.outputDir = mDir.filePath( QStringLiteral( "photo" ) ).toStdString();
  geostation::simulateSurvey( options );
  mTruth = geostation::readTruth( options.outputDir / "truth.gpkg" );
  mTruthBlock = std::make_unique<geostation::Block>( geostation::Block::load( options.outputDir / "truth.geostation.json" ) );
  // the photo as a user has it after Add Photo and Inner Orientation: its fiducials measured, no exterior orientation
  geostation::Block block = geostation::Block::load( options.outputDir / "block.geostation.json" );
  block.images.front().innerOrientation = mTruthBlock->images.front().innerOrientation;
  block.images.front().exterior.reset();
  mBlockPath = mDir.filePath( QStringLiteral( "photo/photo.geostation.json" ) );
  block.save( mBlockPath.toStdString() );
}

void TestOrientationDock::cleanupTestCase()
{
  QgsProject::instance()->clear();
}

std::optional<QPointF> TestOrientationDock::truePixel( const std::string &id ) const
{
  const geostation::BlockImage &image = mTruthBlock->images.front();
  if ( !mTruth.imageTruth.count( { id, image.id } ) )
    return std::nullopt;
  const geostation::Camera &camera = mTruthBlock->cameraOf( image );
  const Eigen::Vector2d nominal = geostation::OrientedImage( camera, *image.exterior ).projectGroundToPixel( mTruth.control.at( id ) ).pixelInImage;
  const Eigen::Matrix<double, 2, 3> a = geostation::nominalFromScanAffine( camera, *image.innerOrientation );
  const Eigen::Vector2d scan = a.leftCols<2>().inverse() * ( nominal - a.col( 2 ) );
  return QPointF( scan.x(), scan.y() );
}

void TestOrientationDock::clickedAndFoundControlOrientTheScannedPhoto()
{
  GeoStationMultiviewSession session;
  QString error;
  QVERIFY2( session.openBlock( mBlockPath, &error ), qPrintable( error ) );
  GeoStationMeasurementStore store( &session, QgsProject::instance() );
  GeoStationMeasurementController controller( &session, &store );
  GeoStationMultiviewDock multiview( &session, &controller, &store );
  QgsMapCanvas canvas;
  canvas.setDestinationCrs( session.crs() );
  QgsRasterLayer *dem = new QgsRasterLayer( mDir.filePath( QStringLiteral( "photo/terrain.tif" ) ), QStringLiteral( "terrain" ) );
  QVERIFY( dem->isValid() );
  QgsProject::instance()->addMapLayer( dem );
  session.setDemLayerId( dem->id() );
  QgsVectorLayer *control = new QgsVectorLayer( mDir.filePath( QStringLiteral( "photo/truth.gpkg|layername=control" ) ), QStringLiteral( "control" ), QStringLiteral( "ogr" ) );
  QVERIFY( control->isValid() );
  QgsProject::instance()->addMapLayer( control );

  GeoStationOrientationDock dock( &session, &multiview, &canvas );
  GeoStationControlPointModel *model = dock.model();
  const QString imageId = QString::fromStdString( mTruthBlock->images.front().id );
  QCOMPARE( dock.imageId(), imageId );
  QCOMPARE( multiview.view( 0 )->imageId(), imageId ); // the photo opens in the Multiview
  const int loaded = dock.loadControlLayer( control );
  QCOMPARE( loaded, static_cast<int>( mTruth.control.size() ) );
  QCOMPARE( model->summary().status, geostation::PhotoOrientationSummary::Status::NotEnoughPoints );

  // four clicks in the photo's view, spread over the photo; the rest of the points visible kept as checks later
  std::vector<std::pair<double, std::string>> visible;
  for ( const auto &[id, world] : mTruth.control )
    if ( const auto pixel = truePixel( id ) )
      visible.emplace_back( pixel->x(), id );
  std::sort( visible.begin(), visible.end() );
  QVERIFY( visible.size() >= 10 );
  std::mt19937 random( 3 );
  std::normal_distribution<double> gauss( 0.0, 0.8 ); // an operator's click on a zoomed view
  dock.findChild<QToolButton *>( QStringLiteral( "mMeasurePhotoButton" ) )->setChecked( true );
  QVERIFY( multiview.pickingRedirected() );
  QStringList clicked;
  for ( size_t k : { size_t( 0 ), visible.size() / 3, 2 * visible.size() / 3, visible.size() - 1 } )
  {
    const QString id = QString::fromStdString( visible[k].second );
    dock.selectRow( model->rowOf( id ) );
    const QPointF truth = *truePixel( visible[k].second );
    emit multiview.view( 0 )->pixelPicked( 0, truth + QPointF( gauss( random ), gauss( random ) ) );
    clicked << id;
  }
  QVERIFY2( model->summary().oriented(), model->summary().message.c_str() );
  QVERIFY( dock.resultText().contains( QStringLiteral( "Oriented from 4 control points" ) ) );
  // the operator-aided mode: the four clicks moved onto the centres of their marks
  const double clickedRmse = model->summary().resection.rmseControlPx;
  for ( const QString &id : std::as_const( clicked ) )
    dock.findChild<QTableView *>( QStringLiteral( "mTable" ) )->selectionModel()->select( model->index( model->rowOf( id ), 0 ), QItemSelectionModel::Select | QItemSelectionModel::Rows );
  std::map<QString, Eigen::Vector2d> asClicked;
  for ( const QString &id : std::as_const( clicked ) )
    asClicked[id] = *model->points()[static_cast<size_t>( model->rowOf( id ) )].pixelInFile;
  const int moved = dock.refineSelected();
  QVERIFY2( moved >= 2, qPrintable( dock.message() ) ); // a target partly hidden or at a grazing angle has no mark to move to: it stays as clicked
  int movedWithin = 0;
  for ( const QString &id : std::as_const( clicked ) )
  {
    const Eigen::Vector2d refined = *model->points()[static_cast<size_t>( model->rowOf( id ) )].pixelInFile;
    const QPointF truth = *truePixel( id.toStdString() );
    const double clickError = std::hypot( asClicked[id].x() - truth.x(), asClicked[id].y() - truth.y() );
    const double refinedError = std::hypot( refined.x() - truth.x(), refined.y() - truth.y() );
    if ( ( refined - asClicked[id] ).norm() > 0.0 )
      movedWithin += refinedError < 0.7 && refinedError < clickError ? 1 : 0;
  }
  QCOMPARE( movedWithin, moved );
  qInfo() << "four clicks: control rmse" << clickedRmse << "px, refined to their marks" << model->summary().resection.rmseControlPx << "px";
  QVERIFY( dock.resultText().contains( QStringLiteral( "X0" ) ) );

  // the semi-automatic mode: the rest predicted, found and offered; nothing taken before the operator accepts
  const int found = dock.predictAndFind();
  QVERIFY2( found >= 5, qPrintable( dock.message() ) );
  QCOMPARE( model->summary().measuredControl, 4 );
  int offersRight = 0, offersWrong = 0;
  for ( const auto &[id, offer] : model->offers() )
    if ( offer.status == geostation::PredictedPoint::Status::Found )
    {
      const auto truth = truePixel( id );
      const double error = truth ? std::hypot( offer.pixelInFile.x() - truth->x(), offer.pixelInFile.y() - truth->y() ) : 1e9;
      ( error <= 1.0 ? offersRight : offersWrong ) += 1;
    }
  QVERIFY( offersWrong <= 1 );
  QVERIFY( dock.markerCount() >= 4 + found ); // clicks and offers drawn in the photo's view
  // the operator reviews the offers flagged because the other points hardly check them (alone near an edge of
  // the photo: they strengthen the orientation most) and selects those that sit on their mark
  QItemSelectionModel *selection = dock.findChild<QTableView *>( QStringLiteral( "mTable" ) )->selectionModel();
  selection->clearSelection();
  int reviewed = 0;
  for ( const auto &[id, offer] : model->offers() )
  {
    const auto truth = truePixel( id );
    if ( offer.status == geostation::PredictedPoint::Status::Flagged && offer.reason.find( "hardly check" ) != std::string::npos && truth &&
         std::hypot( offer.pixelInFile.x() - truth->x(), offer.pixelInFile.y() - truth->y() ) <= 1.0 )
    {
      selection->select( model->index( model->rowOf( QString::fromStdString( id ) ), 0 ), QItemSelectionModel::Select | QItemSelectionModel::Rows );
      ++reviewed;
    }
  }
  QCOMPARE( dock.acceptFound(), found + reviewed );
  QVERIFY( model->summary().oriented() );
  QCOMPARE( model->summary().measuredControl, 4 + found + reviewed );

  // the camera against the truth, and the check-point error against the true orientation's
  const Eigen::Vector3d trueCentre = mTruthBlock->images.front().exterior->projectionCentre;
  const double centreError = ( model->summary().resection.exterior.projectionCentre - trueCentre ).norm();
  qInfo() << "camera" << centreError << "m from the truth from" << model->summary().measuredControl << "points;" << offersRight << "offers within 1 px;" << reviewed
          << "flagged as hardly checked, reviewed and accepted";
  QVERIFY( centreError < 1.0 );

  // a blunder: one clicked point 15 px off is flagged, with its w, and left out; switched off, it is ignored
  const int blunderRow = model->rowOf( clicked[1] );
  dock.selectRow( blunderRow );
  const QPointF truth = *truePixel( clicked[1].toStdString() );
  emit multiview.view( 0 )->pixelPicked( 0, truth + QPointF( 12.0, -9.0 ) );
  QVERIFY( model->summary().points[static_cast<size_t>( blunderRow )].blunder );
  const QString status = model->data( model->index( blunderRow, static_cast<int>( GeoStationControlPointModel::Column::Status ) ) ).toString();
  QVERIFY2( status.startsWith( QStringLiteral( "blunder: w " ) ), qPrintable( status ) );
  QVERIFY( dock.resultText().contains( QStringLiteral( "flagged as a blunder and left out" ) ) );
  QVERIFY( model->setData( model->index( blunderRow, static_cast<int>( GeoStationControlPointModel::Column::Use ) ), Qt::Unchecked, Qt::CheckStateRole ) );
  QVERIFY( !model->summary().points[static_cast<size_t>( blunderRow )].blunder );
  QVERIFY( ( model->summary().resection.exterior.projectionCentre - trueCentre ).norm() < 1.0 );

  // check points, each measured point in turn (leave one out): the resection's error on them against the true
  // orientation's (which is their measurement error alone), over the same points
  double resectionSquares = 0.0, trueSquares = 0.0;
  int checked = 0;
  for ( int row = 0; row < model->rowCount(); ++row )
  {
    const geostation::PhotoControlPoint point = model->points()[static_cast<size_t>( row )];
    if ( !point.pixelInFile || point.role != geostation::ControlRole::Control )
      continue;
    QVERIFY( model->setData( model->index( row, static_cast<int>( GeoStationControlPointModel::Column::Check ) ), Qt::Checked, Qt::CheckStateRole ) );
    QVERIFY( model->summary().oriented() );
    QCOMPARE( model->summary().measuredCheck, 1 );
    resectionSquares += std::pow( model->summary().resection.rmseCheckPx, 2 );
    const QPointF t = *truePixel( point.pointId );
    trueSquares += std::pow( point.pixelInFile->x() - t.x(), 2 ) + std::pow( point.pixelInFile->y() - t.y(), 2 );
    ++checked;
    QVERIFY( model->setData( model->index( row, static_cast<int>( GeoStationControlPointModel::Column::Check ) ), Qt::Unchecked, Qt::CheckStateRole ) );
  }
  const double resectionRms = std::sqrt( resectionSquares / checked ), trueRms = std::sqrt( trueSquares / checked );
  qInfo() << "check points (each of" << checked << "in turn): the resection" << resectionRms << "px, the true orientation" << trueRms << "px";
  QVERIFY( checked >= 8 );
  QVERIFY( resectionRms <= 1.5 * trueRms );
  // four of them as check points for the rest of the session
  int checks = 0;
  for ( int row = 0; row < model->rowCount() && checks < 4; ++row )
    if ( model->points()[static_cast<size_t>( row )].pixelInFile && model->points()[static_cast<size_t>( row )].role == geostation::ControlRole::Control )
    {
      QVERIFY( model->setData( model->index( row, static_cast<int>( GeoStationControlPointModel::Column::Check ) ), Qt::Checked, Qt::CheckStateRole ) );
      ++checks;
    }
  QCOMPARE( model->summary().measuredCheck, 4 );

  // the map's roads drawn in the photo with the orientation being measured, hidden parts marked; following the layer's edits
  QgsVectorLayer *roads = new QgsVectorLayer( mDir.filePath( QStringLiteral( "photo/truth.gpkg|layername=roads" ) ), QStringLiteral( "roads" ), QStringLiteral( "ogr" ) );
  QVERIFY( roads->isValid() );
  QgsProject::instance()->addMapLayer( roads );
  dock.layerInPhoto()->setLayer( roads );
  const int visibleRuns = dock.layerInPhoto()->visibleParts(), hiddenRuns = dock.layerInPhoto()->hiddenParts();
  qInfo() << "roads in the photo:" << visibleRuns << "visible runs," << hiddenRuns << "hidden behind the terrain," << dock.layerInPhoto()->skippedFeatures() << "skipped";
  QVERIFY( visibleRuns >= 10 );
  QVERIFY( hiddenRuns >= 2 );
  QCOMPARE( dock.layerInPhoto()->skippedFeatures(), 0 );
  QVERIFY( roads->startEditing() );
  QgsFeatureIds all;
  QgsFeatureIterator roadFeatures = roads->getFeatures();
  QgsFeature road;
  while ( roadFeatures.nextFeature( road ) )
    all.insert( road.id() );
  QVERIFY( roads->deleteFeatures( all ) );
  QTRY_COMPARE_WITH_TIMEOUT( dock.layerInPhoto()->visibleParts(), 0, 3000 ); // the edit buffer, before any save
  roads->rollBack();
  QTRY_COMPARE_WITH_TIMEOUT( dock.layerInPhoto()->visibleParts(), visibleRuns, 3000 );

  // a ground click off the DEM: one sentence, nothing changed
  const int rows = model->rowCount();
  dock.selectRow( 0 );
  const Eigen::Vector3d before = model->points()[0].world;
  QVERIFY( !dock.pickGround( QgsPointXY( trueCentre.x() + 1e6, trueCentre.y() ) ) );
  QVERIFY2( dock.message().contains( QStringLiteral( "outside the DEM" ) ), qPrintable( dock.message() ) );
  QCOMPARE( model->rowCount(), rows );
  QVERIFY( ( model->points()[0].world - before ).norm() == 0.0 );
  // a ground click on the DEM moves the selected point there, with the DEM's height
  const Eigen::Vector3d onDem = mTruth.control.begin()->second;
  dock.selectRow( model->addPoint() );
  QVERIFY2( dock.pickGround( QgsPointXY( onDem.x(), onDem.y() ) ), qPrintable( dock.message() ) );
  QVERIFY( std::abs( model->points().back().world.z() - onDem.z() ) < 1.0 );
  model->removePoint( model->rowCount() - 1 );

  // how much of the photo's ground the DEM layer covers, told with the result: as under the true orientation
  QVERIFY( dock.demCoverage().has_value() );
  QVERIFY( dock.resultText().contains( QStringLiteral( "DEM: " ) + QString::fromStdString( dock.demCoverage()->message ) ) );
  {
    const geostation::Dem terrain( mDir.filePath( QStringLiteral( "photo/terrain.tif" ) ).toStdString() );
    const geostation::CrsTransform same( mTruthBlock->crs, terrain.crsWkt() );
    const geostation::OrientedImage trueImage = mTruthBlock->orientedImage( mTruthBlock->images.front() );
    const geostation::Monoplotter monoplotter( trueImage, terrain, same );
    const geostation::DemCoverageSummary truth = geostation::demCoverageOfImage( monoplotter );
    qInfo() << "DEM coverage:" << dock.demCoverage()->message.c_str() << "- with the true orientation" << truth.onDem << "of" << truth.groundSamples() << "rays on it," << truth.sky << "at the sky";
    QVERIFY( std::abs( dock.demCoverage()->onDem - truth.onDem ) <= 2 );
    QVERIFY( std::abs( dock.demCoverage()->sky - truth.sky ) <= 2 );
  }

  // saved into the block: the file reloads oriented, the measurements beside it come back with the photo
  QVERIFY2( dock.saveToBlock(), qPrintable( dock.message() ) );
  if ( !dock.demCoverage()->complete() )
    QVERIFY2( dock.message().contains( QStringLiteral( "Note: the DEM covers" ) ), qPrintable( dock.message() ) );
  const geostation::Block saved = geostation::Block::load( mBlockPath.toStdString() );
  QVERIFY( saved.images.front().exterior.has_value() );
  QVERIFY( ( saved.images.front().exterior->projectionCentre - model->summary().resection.exterior.projectionCentre ).norm() < 1e-6 );
  QVERIFY( session.block()->images.front().exterior.has_value() );
  QCOMPARE( dock.imageId(), imageId );
  GeoStationOrientationDock again( &session, &multiview, &canvas );
  QCOMPARE( again.model()->rowCount(), model->rowCount() );
  QCOMPARE( again.model()->summary().measuredControl, model->summary().measuredControl );
  QCOMPARE( again.model()->summary().measuredCheck, 4 );

  // digitising in the oriented photo: a line on the DEM follows the terrain between the clicks; Backspace takes a click back with them
  QList<GeoStationFeatureClass> classes;
  QVERIFY( GeoStationFeatureClass::fromJson( QStringLiteral( R"([{"name":"Track","geometry":"line"}])" ), classes, &error ) );
  session.setFeatureClasses( classes );
  session.setCurrentClass( QStringLiteral( "Track" ) );
  session.setTargetGeoPackage( mDir.filePath( QStringLiteral( "photo/tracks.gpkg" ) ) );
  controller.viewsChanged();
  controller.pick( 0, QPointF( 300.0, 500.0 ) );
  QVERIFY( controller.acceptPoint() );
  QCOMPARE( controller.vertexCount(), 1 );
  controller.pick( 0, QPointF( 600.0, 520.0 ) );
  QVERIFY( controller.acceptPoint() );
  QCOMPARE( controller.vertexCount(), 17 ); // 301 px: 15 vertices on the terrain between the two clicks
  QCOMPARE( controller.lastVertex()->method, geostation::VertexMethod::MonoplotDem );
  controller.undoVertex();
  QCOMPARE( controller.vertexCount(), 1 );
  controller.cancel();

  // a photo that can no longer be decoded: one sentence, the measurements stay
  QFile file( session.imagePath( imageId ) );
  QVERIFY( QFile::copy( file.fileName(), file.fileName() + QStringLiteral( ".kept" ) ) );
  QVERIFY( file.open( QIODevice::WriteOnly | QIODevice::Truncate ) );
  file.write( "not an image" );
  file.close();
  const int measured = again.model()->summary().measuredControl;
  QCOMPARE( again.predictAndFind(), 0 );
  QVERIFY2( again.message().startsWith( QStringLiteral( "The photo cannot be read" ) ), qPrintable( again.message() ) );
  QCOMPARE( again.model()->summary().measuredControl, measured );
  QVERIFY( QFile::remove( file.fileName() ) && QFile::rename( file.fileName() + QStringLiteral( ".kept" ), file.fileName() ) );
}

void TestOrientationDock::addPhotoStartsABlockAndOpensThePhotoUnoriented()
{
  const geostation::BlockImage &truthImage = mTruthBlock->images.front();
  const QString photo = QString::fromStdString( mTruthBlock->imageFilePath( truthImage ).string() );
  const geostation::Camera &film = mTruthBlock->cameraOf( truthImage );
  // the film camera as its calibration report gives it: principal distance, principal point, lens distortion, pixel size, fiducials
  QFile truthFile( mDir.filePath( QStringLiteral( "photo/truth.geostation.json" ) ) );
  QVERIFY( truthFile.open( QIODevice::ReadOnly ) );
  QJsonObject cameraObject = QJsonDocument::fromJson( truthFile.readAll() ).object().value( QStringLiteral( "cameras" ) ).toArray().at( 0 ).toObject();
  cameraObject.insert( QStringLiteral( "id" ), QStringLiteral( "rmk" ) );
  const QString cameraJson = QString::fromUtf8( QJsonDocument( cameraObject ).toJson( QJsonDocument::Compact ) );
  GeoStationMultiviewSession session;
  geostation::Camera camera;
  QString error;
  QVERIFY2( GeoStationAddPhotoDialog::cameraForPhoto( nullptr, photo, cameraJson, &camera, &error ), qPrintable( error ) );
  QCOMPARE( camera.fiducials.size(), film.fiducials.size() );
  const QString blockPath = mDir.filePath( QStringLiteral( "added/new.geostation.json" ) );
  QDir().mkpath( mDir.filePath( QStringLiteral( "added" ) ) );
  const QgsCoordinateReferenceSystem crs( QString::fromStdString( mTruthBlock->crs ) );
  // bad input first: a geographic CRS, a file that is no photo: one sentence, no block written
  QVERIFY( GeoStationAddPhotoDialog::addToBlock( &session, photo, camera, blockPath, QgsCoordinateReferenceSystem( QStringLiteral( "EPSG:4326" ) ), &error ).isEmpty() );
  QVERIFY2( error.contains( QStringLiteral( "projected CRS" ) ), qPrintable( error ) );
  QFile broken( mDir.filePath( QStringLiteral( "added/broken.jpg" ) ) );
  QVERIFY( broken.open( QIODevice::WriteOnly ) );
  broken.write( "not a photo" );
  broken.close();
  QVERIFY( GeoStationAddPhotoDialog::addToBlock( &session, broken.fileName(), camera, blockPath, crs, &error ).isEmpty() );
  QVERIFY2( error.contains( QStringLiteral( "cannot be decoded" ) ), qPrintable( error ) );
  QVERIFY( !QFileInfo::exists( blockPath ) );
  QVERIFY( !session.hasBlock() );

  const QString imageId = GeoStationAddPhotoDialog::addToBlock( &session, photo, camera, blockPath, crs, &error );
  QVERIFY2( !imageId.isEmpty(), qPrintable( error ) );
  QVERIFY( session.hasBlock() );
  QCOMPARE( session.blockPath(), blockPath );
  QVERIFY( !session.block()->image( imageId.toStdString() ).exterior.has_value() );
  GeoStationOrientationDock dock( &session, nullptr, nullptr );
  QVERIFY( dock.setImage( imageId ) );
  QCOMPARE( dock.model()->summary().status, geostation::PhotoOrientationSummary::Status::NotEnoughPoints );
  QVERIFY( !dock.model()->nominalFromFile().has_value() );

  // the fiducials: detected in the four corners, the affine and its decomposition live, against the simulator's truth
  GeoStationFiducialPanel *panel = dock.fiducialPanel();
  QCOMPARE( panel->model()->rowCount(), static_cast<int>( film.fiducials.size() ) );
  {
    // in the background: the button reads Cancel Detection until the corners are read
    QSignalSpy detected( panel, &GeoStationFiducialPanel::detectionFinished );
    QVERIFY( panel->detect() );
    QVERIFY( !panel->detect() ); // one at a time
    QCOMPARE( panel->findChild<QToolButton *>( QStringLiteral( "mDetectButton" ) )->text(), QStringLiteral( "Cancel Detection" ) );
    QVERIFY( detected.wait( 60000 ) );
    QCOMPARE( detected.at( 0 ).at( 0 ).toInt(), 4 );
    QCOMPARE( panel->findChild<QToolButton *>( QStringLiteral( "mDetectButton" ) )->text(), QStringLiteral( "Detect Fiducials" ) );
  }
  QVERIFY2( panel->resultText().contains( QStringLiteral( "affinity" ) ), qPrintable( panel->resultText() ) );
  QVERIFY( dock.model()->nominalFromFile().has_value() );
  const geostation::ImageInnerOrientation &trueInner = *truthImage.innerOrientation;
  double worstMm = 0.0;
  for ( const Eigen::Vector2d &corner : { Eigen::Vector2d( 0, 0 ), Eigen::Vector2d( film.width, 0 ), Eigen::Vector2d( film.width, film.height ), Eigen::Vector2d( 0, film.height ) } )
    worstMm = std::max( worstMm, ( ( panel->innerOrientation()->photoFromPixel - trueInner.photoFromPixel ) * corner.homogeneous() ).norm() );
  qInfo() << "inner orientation from the detected fiducials:" << panel->resultText() << "; worst error at the scan's corners" << 1000.0 * worstMm << "µm";
  QVERIFY( worstMm < 0.5 * *film.pixelSizeMm );
  // a fiducial corrected by a click: the residuals follow at once
  const int row = panel->model()->rowOf( QString::fromStdString( geostation::cornerFiducialIds( film.fiducials )[0] ) );
  const QPointF detected = *panel->model()->measurement( row );
  panel->selectRow( row );
  panel->measurePixel( detected + QPointF( 3.0, 0.0 ) );
  QVERIFY( panel->model()->summary().rmsResidualMm > 0.3 * *film.pixelSizeMm );
  panel->selectRow( row );
  panel->measurePixel( detected );
  QVERIFY( panel->model()->summary().rmsResidualMm < 0.3 * *film.pixelSizeMm );

  // the control layer; with nothing measured, the control is identified among the photo's marks and offered
  QgsVectorLayer control( mDir.filePath( QStringLiteral( "photo/truth.gpkg|layername=control" ) ), QStringLiteral( "control" ), QStringLiteral( "ogr" ) );
  QCOMPARE( dock.loadControlLayer( &control ), static_cast<int>( mTruth.control.size() ) );
  // unoriented, this photo shows too few clear targets for the search to rule chance out: it says so and offers nothing
  const int unguided = identified( dock );
  qInfo() << "identified with no orientation:" << dock.message();
  if ( unguided == 0 )
  {
    QVERIFY2( dock.message().startsWith( QStringLiteral( "No control identified among" ) ), qPrintable( dock.message() ) );
    QVERIFY( dock.model()->offers().empty() );
  }
  QCOMPARE( dock.model()->summary().measuredControl, 0 ); // offers are never taken by themselves
  dock.model()->rejectOffers();

  // three points clicked are enough to start the semi-automatic mode (P3P; the photo picks among its solutions)
  QCOMPARE( dock.predictAndFind(), 0 );
  QVERIFY2( dock.message().contains( QStringLiteral( "Measure three points first" ) ), qPrintable( dock.message() ) );
  std::vector<std::pair<double, std::string>> visible;
  for ( const auto &[id, world] : mTruth.control )
    if ( const auto pixel = truePixel( id ) )
      visible.emplace_back( pixel->x(), id );
  std::sort( visible.begin(), visible.end() );
  for ( size_t k : { size_t( 0 ), visible.size() / 2, visible.size() - 1 } )
  {
    dock.selectRow( dock.model()->rowOf( QString::fromStdString( visible[k].second ) ) );
    dock.measurePixel( *truePixel( visible[k].second ) );
  }
  QCOMPARE( dock.model()->summary().status, geostation::PhotoOrientationSummary::Status::NotEnoughPoints );
  const int foundFromThree = dock.predictAndFind();
  qInfo() << "three clicks:" << dock.message();
  QVERIFY2( foundFromThree >= 5, qPrintable( dock.message() ) );
  QCOMPARE( dock.acceptFound(), foundFromThree );
  QVERIFY2( dock.model()->summary().oriented(), dock.model()->summary().message.c_str() );
  qInfo() << "camera" << ( dock.model()->summary().resection.exterior.projectionCentre - truthImage.exterior->projectionCentre ).norm() << "m from the truth:" << dock.model()->summary().message.c_str();
  QVERIFY( ( dock.model()->summary().resection.exterior.projectionCentre - truthImage.exterior->projectionCentre ).norm() < 1.0 );
  // oriented, the identification searches near each prediction and pairs the marks
  // the search runs in the background: the button stops it, nothing new is offered and the dock says so
  {
    QToolButton *button = dock.findChild<QToolButton *>( QStringLiteral( "mIdentifyButton" ) );
    QSignalSpy finished( &dock, &GeoStationOrientationDock::identificationFinished );
    const size_t offersBefore = dock.model()->offers().size();
    QVERIFY( dock.identifyAutomatically() );
    QCOMPARE( button->text(), QStringLiteral( "Cancel Identification" ) );
    QVERIFY( !dock.identifyAutomatically() ); // one at a time
    button->click();
    QVERIFY( finished.wait( 60000 ) );
    QCOMPARE( finished.at( 0 ).at( 0 ).toInt(), 0 );
    QVERIFY2( dock.message().contains( QStringLiteral( "cancelled" ) ), qPrintable( dock.message() ) );
    QCOMPARE( dock.model()->offers().size(), offersBefore ); // nothing new offered
    QCOMPARE( button->text(), QStringLiteral( "Identify Automatically" ) );
  }
  const int guided = identified( dock );
  qInfo() << "identified with the orientation:" << dock.message();
  QVERIFY2( guided >= 6, qPrintable( dock.message() ) );

  // the dialog: a photo that cannot be read says so; a readable one is prefilled from the file
  GeoStationAddPhotoDialog dialog( nullptr, crs );
  dialog.setPhotoPath( broken.fileName() );
  QVERIFY2( dialog.problem().contains( QStringLiteral( "cannot be decoded" ) ), qPrintable( dialog.problem() ) );
  // a phone photo tagged to be shown turned: the dialog says it is shown turned and measured as stored
  const QString turned = mDir.filePath( QStringLiteral( "added/turned.jpg" ) );
  {
    GDALDatasetH source = GDALOpen( photo.toUtf8().constData(), GA_ReadOnly );
    QVERIFY( source );
    GDALDatasetH memory = GDALCreateCopy( GDALGetDriverByName( "MEM" ), "", source, FALSE, nullptr, nullptr, nullptr );
    GDALClose( source );
    GDALSetMetadataItem( memory, "EXIF_Orientation", "6", nullptr );
    GDALClose( GDALCreateCopy( GDALGetDriverByName( "JPEG" ), turned.toUtf8().constData(), memory, FALSE, nullptr, nullptr, nullptr ) );
    GDALClose( memory );
  }
  dialog.setPhotoPath( turned );
  const QString turnedNote = dialog.findChild<QLabel *>( QStringLiteral( "mFocalNote" ) )->text();
  QVERIFY2( turnedNote.contains( QStringLiteral( "The file is tagged to be shown turned 90 degrees clockwise (EXIF orientation 6); its views show it so, but its pixels are measured as stored" ) ), qPrintable( turnedNote ) );
  dialog.setPhotoPath( photo );
  QVERIFY( dialog.problem().isEmpty() );
  QVERIFY( !dialog.findChild<QLabel *>( QStringLiteral( "mFocalNote" ) )->text().contains( QStringLiteral( "EXIF orientation" ) ) );
  QVERIFY( dialog.camera( &camera, &error ) );
  QCOMPARE( camera.width, film.width );
  // a calibration report's values typed in: principal distance, pixel size, lens distortion, fiducials
  dialog.findChild<QDoubleSpinBox *>( QStringLiteral( "mPixelSpin" ) )->setValue( *film.pixelSizeMm );
  dialog.findChild<QDoubleSpinBox *>( QStringLiteral( "mFSpin" ) )->setValue( film.f );
  QComboBox *model = dialog.findChild<QComboBox *>( QStringLiteral( "mDistortionCombo" ) );
  model->setCurrentText( QStringLiteral( "brown_photo" ) );
  QLineEdit *coefficients = dialog.findChild<QLineEdit *>( QStringLiteral( "mDistortionEdit" ) );
  coefficients->setText( QStringLiteral( "%1 %2 %3 %4" ).arg( film.distortion.k1(), 0, 'g', 17 ).arg( film.distortion.k2(), 0, 'g', 17 ).arg( film.distortion.p1(), 0, 'g', 17 ).arg( film.distortion.p2(), 0, 'g', 17 ) );
  QString typedFiducials;
  for ( const geostation::Fiducial &f : film.fiducials )
    typedFiducials += QStringLiteral( "%1 %2 %3\n" ).arg( QString::fromStdString( f.id ) ).arg( f.photoMm.x(), 0, 'g', 17 ).arg( f.photoMm.y(), 0, 'g', 17 );
  dialog.findChild<QPlainTextEdit *>( QStringLiteral( "mFiducialEdit" ) )->setPlainText( typedFiducials );
  QVERIFY2( dialog.camera( &camera, &error ), qPrintable( error ) );
  QCOMPARE( camera.fiducials.size(), film.fiducials.size() );
  QCOMPARE( camera.distortion.k1(), film.distortion.k1() );
  QCOMPARE( camera.distortion.p2(), film.distortion.p2() );
  coefficients->setText( QStringLiteral( "1e-6 x" ) );
  QVERIFY( !dialog.camera( &camera, &error ) );
  QVERIFY2( error.contains( QStringLiteral( "k1 k2 p1 p2 k3" ) ), qPrintable( error ) );
  QVERIFY( dialog.newBlockPath().endsWith( QStringLiteral( ".geostation.json" ) ) );
}

int main( int argc, char **argv )
{
  QgsApplication app( argc, argv, true );
  QgsApplication::init();
  QgsApplication::initQgis();
  int result = 0;
  {
    TestOrientationDock test;
    result = QTest::qExec( &test, argc, argv );
  }
  QgsApplication::exitQgis();
  return result;
}

#include "testorientationdock.moc"

/***************************************************************************
  geostationplugin.cpp - the GeoStation plugin for QGIS desktop
 ***************************************************************************/
#include "geostationplugin.h"
#include "extractionreview.h"
#include "revisiondock.h"
#include "reviewtool.h"

#include <QAction>
#include <QJsonDocument>
#include <QJsonObject>
#include <QDesktopServices>
#include <QUrl>
#include <QFileDialog>
#include <QInputDialog>
#include <QFileInfo>
#include <QMainWindow>
#include <QMenu>
#include <QMenuBar>
#include <QToolBar>

#include <qgisinterface.h>
#include <qgsmapcanvas.h>
#include <qgsmessagebar.h>
#include <qgsapplication.h>
#include <qgsprocessingalgorithm.h>
#include <qgsprocessingregistry.h>
#include <qgsproject.h>
#include <qgspythonrunner.h>
#include <qgssettings.h>

#include "addphotodialog.h"
#include "blockinfodialog.h"
#include "featureclassdialog.h"
#include "geostationprovider.h"
#include "userguide.h"
#include "io/block.h"
#include "measurementcontroller.h"
#include "measurementsettingsdialog.h"
#include "measurementstore.h"
#include "tracecontroller.h"
#include "multiviewdock.h"
#include "orientationdock.h"
#include "multiviewsession.h"
#include "overviewlayers.h"
#include "mappointtool.h"

namespace
{
  const QString sName = QStringLiteral( "GeoStation" );
  const QString sDescription = QStringLiteral( "Softcopy photogrammetry: multiview measurement, monoplotting and road tracing from oriented imagery" );
  const QString sCategory = QStringLiteral( "Plugins" );
  const QString sVersion = QStringLiteral( GEOSTATION_VERSION ); // project( VERSION ) in CMakeLists.txt
  const QString sIcon = QStringLiteral( ":/geostation/icons/geostation.svg" );
  const QgisPlugin::PluginType sPluginType = QgisPlugin::UI;
  const QString sLastBlockDirKey = QStringLiteral( "geostation/lastBlockDir" );
}

GeoStationPlugin::GeoStationPlugin( QgisInterface *iface )
  : QgisPlugin( sName, sDescription, sCategory, sVersion, sPluginType )
  , mIface( iface )
{
  setObjectName( QStringLiteral( "GeoStationPlugin" ) );
}

GeoStationPlugin::~GeoStationPlugin() = default;

const geostation::Block *GeoStationPlugin::block() const
{
  return mSession ? mSession->block() : nullptr;
}

QAction *GeoStationPlugin::addAction( const QString &objectName, const QString &icon, const QString &text, const QString &tip, void ( GeoStationPlugin::*slot )() )
{
  QAction *action = new QAction( QIcon( icon ), text, mIface->mainWindow() );
  action->setObjectName( objectName );
  action->setToolTip( tip );
  action->setStatusTip( tip );
  if ( slot )
    connect( action, &QAction::triggered, this, slot );
  mMenu->addAction( action );
  mToolBar->addAction( action );
  mActions << action;
  return action;
}

QAction *GeoStationPlugin::addAlgorithmAction( QMenu *menu, const QString &objectName, const QString &text, const QString &algorithmId )
{
  QAction *action = new QAction( text, mIface->mainWindow() );
  action->setObjectName( objectName );
  connect( action, &QAction::triggered, this, [this, algorithmId] { showAlgorithmDialog( algorithmId ); } );
  menu->addAction( action );
  mActions << action;
  return action;
}

void GeoStationPlugin::initGui()
{
  // Parented to the main window so scripts and tests can find the plugin.
  setParent( mIface->mainWindow() );
  mRegisteredProvider = registerGeoStationProvider();

  QMainWindow *mainWindow = qobject_cast<QMainWindow *>( mIface->mainWindow() );
  QMenuBar *menuBar = mainWindow ? mainWindow->menuBar() : nullptr;
  if ( !menuBar )
    return;
  mMenu = new QMenu( tr( "&GeoStation" ), menuBar );
  mMenu->setObjectName( QStringLiteral( "mGeoStationMenu" ) );
  QAction *before = nullptr;
  for ( QAction *a : menuBar->actions() )
    if ( a->menu() && a->menu()->objectName() == QLatin1String( "mHelpMenu" ) )
      before = a;
  menuBar->insertMenu( before, mMenu );

  mToolBar = mIface->addToolBar( tr( "GeoStation" ) );
  mToolBar->setObjectName( QStringLiteral( "mGeoStationToolBar" ) );

  addAction( QStringLiteral( "mActionGeoStationOpenBlock" ), QStringLiteral( ":/geostation/icons/openblock.svg" ), tr( "Open Block…" ),
             tr( "Open a GeoStation block (*.geostation.json): cameras, stations and oriented images" ), &GeoStationPlugin::openBlock );
  QAction *importBlock = new QAction( tr( "Import Block…" ), mIface->mainWindow() );
  importBlock->setObjectName( QStringLiteral( "mActionGeoStationImportBlock" ) );
  importBlock->setToolTip( tr( "Import a COLMAP reconstruction, or a calibration with its trajectory, as a block and open it" ) );
  connect( importBlock, &QAction::triggered, this, &GeoStationPlugin::importBlock );
  mMenu->addAction( importBlock );
  mBlockInfoAction = addAction( QStringLiteral( "mActionGeoStationBlockInfo" ), QStringLiteral( ":/geostation/icons/blockinfo.svg" ), tr( "Block Information…" ),
                                tr( "Show the cameras (interior orientation), stations and images of the open block" ), &GeoStationPlugin::showBlockInfo );
  QAction *project = addAction( QStringLiteral( "mActionGeoStationProjectToImage" ), QStringLiteral( ":/geostation/icons/projecttoimage.svg" ), tr( "Project Map Points to Image…" ),
                                tr( "Find where map points with heights appear in an oriented image" ), nullptr );
  connect( project, &QAction::triggered, this, [this] { showAlgorithmDialog( QStringLiteral( "geostation:project_to_image" ) ); } );

  addAlgorithmAction( mMenu, QStringLiteral( "mActionGeoStationMonoplot" ), tr( "Monoplot Image Features onto a DEM…" ), QStringLiteral( "geostation:monoplot" ) );
  QAction *addPhotoAction = new QAction( tr( "Add Photo…" ), mIface->mainWindow() );
  addPhotoAction->setObjectName( QStringLiteral( "mActionGeoStationAddPhoto" ) );
  addPhotoAction->setToolTip( tr( "Add a photo, unoriented, to the open block (or to a new block) and open it for orientation" ) );
  connect( addPhotoAction, &QAction::triggered, this, &GeoStationPlugin::addPhoto );
  mMenu->addAction( addPhotoAction );
  QAction *orient = new QAction( tr( "Orient Photo…" ), mIface->mainWindow() );
  orient->setObjectName( QStringLiteral( "mActionGeoStationOrientPhoto" ) );
  orient->setToolTip( tr( "Orient a photo of the block from control points: measure them in the photo and on the map, see the residuals live, find the rest semi-automatically" ) );
  connect( orient, &QAction::triggered, this, &GeoStationPlugin::showOrientation );
  mMenu->addAction( orient );

  // the Multiview, the Overview and measuring
  mSession = new GeoStationMultiviewSession( this );
  mStore = new GeoStationMeasurementStore( mSession, QgsProject::instance(), this );
  mController = new GeoStationMeasurementController( mSession, mStore, this );
  mOverview = new GeoStationOverviewLayers( mSession, QgsProject::instance(), mIface->mapCanvas(), this );
  mTrace = new GeoStationTraceController( mSession, mStore, this );
  // the line being traced grows on the map too
  connect( mTrace, &GeoStationTraceController::lineChanged, this, [this]
  {
    QVector<QgsPoint> points;
    for ( const Eigen::Vector3d &p : mTrace->line().points() )
      points << QgsPoint( p.x(), p.y(), p.z() );
    mOverview->setTracedLine( points );
  } );
  mMenu->addSeparator();
  mMultiviewAction = addAction( QStringLiteral( "mActionGeoStationMultiview" ), QStringLiteral( ":/geostation/icons/multiview.svg" ), tr( "Multiview" ),
                                tr( "Show the image views of the current station and measure in them" ), &GeoStationPlugin::showMultiview );
  mPickStationAction = addAction( QStringLiteral( "mActionGeoStationPickStation" ), QStringLiteral( ":/geostation/icons/pickstation.svg" ), tr( "Pick Station on Map" ),
                                  tr( "Click near the trajectory on the map to load that station into the Multiview" ), nullptr );
  mPickStationAction->setCheckable( true );
  mPickTool = new GeoStationMapPointTool( mIface->mapCanvas(), Qt::PointingHandCursor );
  mPickTool->setAction( mPickStationAction );
  connect( mPickStationAction, &QAction::triggered, this, [this]( bool on )
  {
    if ( on )
      mIface->mapCanvas()->setMapTool( mPickTool );
    else if ( mIface->mapCanvas()->mapTool() == mPickTool )
      mIface->mapCanvas()->unsetMapTool( mPickTool );
  } );
  connect( mPickTool, &GeoStationMapPointTool::picked, this, [this]( const QgsPointXY &point )
  {
    const int index = mOverview->stationNearestToMapPoint( point );
    if ( index < 0 )
      return;
    mSession->setCurrentStation( index );
    showMultiview();
  } );
  // reviewing an extracted road network: click lines of geostation:extract_roads' output on the map
  mReview = new GeoStationExtractionReview( mSession, mStore, this );
  mReviewAction = addAction( QStringLiteral( "mActionGeoStationReviewExtracted" ), QStringLiteral( ":/geostation/icons/reviewroads.svg" ), tr( "Review Extracted Roads" ),
                             tr( "Click an extracted road on the map: left accepts it into the current line class (method \"extracted\"), right rejects it" ), nullptr );
  mReviewAction->setCheckable( true );
  mReviewTool = new GeoStationReviewTool( mIface->mapCanvas() );
  mReviewTool->setAction( mReviewAction );
  connect( mReviewAction, &QAction::triggered, this, [this]( bool on )
  {
    if ( on )
      mIface->mapCanvas()->setMapTool( mReviewTool );
    else if ( mIface->mapCanvas()->mapTool() == mReviewTool )
      mIface->mapCanvas()->unsetMapTool( mReviewTool );
  } );
  connect( mReviewTool, &GeoStationReviewTool::picked, mReview, &GeoStationExtractionReview::review );
  connect( mReviewTool, &GeoStationReviewTool::missed, this, [this]
  {
    mIface->messageBar()->pushMessage( tr( "GeoStation" ), tr( "No extracted road there: add geostation:extract_roads' OUTPUT to the map and click one of its lines." ),
                                       Qgis::MessageLevel::Info, 4 );
  } );
  connect( mReview, &GeoStationExtractionReview::message, this, [this]( const QString &text, bool warning )
  {
    mIface->messageBar()->pushMessage( tr( "GeoStation review" ), text, warning ? Qgis::MessageLevel::Warning : Qgis::MessageLevel::Success, 4 );
  } );
  addAlgorithmAction( mMenu, QStringLiteral( "mActionGeoStationExtractRoads" ), tr( "Extract Roads from a Stereo Pair…" ), QStringLiteral( "geostation:extract_roads" ) );
  addAlgorithmAction( mMenu, QStringLiteral( "mActionGeoStationReviseRoads" ), tr( "Revise a Road Map against a Stereo Pair…" ), QStringLiteral( "geostation:revise_roads" ) );
  QAction *reviewRevision = new QAction( tr( "Review Map Revision" ), mIface->mainWindow() );
  reviewRevision->setObjectName( QStringLiteral( "mActionGeoStationReviewRevision" ) );
  reviewRevision->setToolTip( tr( "List revise_roads' changes, worst evidence first, and accept them into the map layer's edit buffer" ) );
  connect( reviewRevision, &QAction::triggered, this, &GeoStationPlugin::showRevisionReview );
  mMenu->addAction( reviewRevision );
  mActions << reviewRevision;

  QAction *goTo = new QAction( tr( "Go to Coordinate…" ), mIface->mainWindow() );
  goTo->setObjectName( QStringLiteral( "mActionGeoStationGoTo" ) );
  connect( goTo, &QAction::triggered, this, &GeoStationPlugin::goToCoordinate );
  mMenu->addAction( goTo );
  mActions << goTo;
  QAction *classes = new QAction( tr( "Feature Classes…" ), mIface->mainWindow() );
  classes->setObjectName( QStringLiteral( "mActionGeoStationFeatureClasses" ) );
  connect( classes, &QAction::triggered, this, &GeoStationPlugin::editFeatureClasses );
  mMenu->addAction( classes );
  mActions << classes;
  QAction *settings = new QAction( tr( "Measurement Settings…" ), mIface->mainWindow() );
  settings->setObjectName( QStringLiteral( "mActionGeoStationMeasurementSettings" ) );
  connect( settings, &QAction::triggered, this, &GeoStationPlugin::editMeasurementSettings );
  mMenu->addAction( settings );
  mActions << settings;
  addAlgorithmAction( mMenu, QStringLiteral( "mActionGeoStationExportMeasurements" ), tr( "Export Measurements to Shapefile and DXF…" ), QStringLiteral( "geostation:export_measurements" ) );
  mMenu->addSeparator();

  connect( QgsProject::instance(), &QgsProject::writeProject, this, [this]( QDomDocument & ) { writeProject(); } );
  connect( QgsProject::instance(), &QgsProject::readProject, this, [this]( const QDomDocument & ) { readProject(); } );
  connect( QgsProject::instance(), &QgsProject::cleared, this, [this] { mSession->closeBlock(); } );
  connect( mSession, &GeoStationMultiviewSession::blockChanged, this, &GeoStationPlugin::updateActions );

  mAdjustmentMenu = mMenu->addMenu( tr( "Adjustment" ) );
  mAdjustmentMenu->setObjectName( QStringLiteral( "mGeoStationAdjustmentMenu" ) );
  addAlgorithmAction( mAdjustmentMenu, QStringLiteral( "mActionGeoStationIntersect" ), tr( "Intersect Image Points…" ), QStringLiteral( "geostation:intersect" ) );
  addAlgorithmAction( mAdjustmentMenu, QStringLiteral( "mActionGeoStationResection" ), tr( "Space Resection…" ), QStringLiteral( "geostation:resection" ) );
  addAlgorithmAction( mAdjustmentMenu, QStringLiteral( "mActionGeoStationBundleAdjust" ), tr( "Bundle Adjustment…" ), QStringLiteral( "geostation:bundle_adjust" ) );
  addAlgorithmAction( mAdjustmentMenu, QStringLiteral( "mActionGeoStationInnerOrientation" ), tr( "Inner Orientation from Fiducials…" ), QStringLiteral( "geostation:inner_orientation" ) );

  mMenu->addSeparator();
  QAction *guide = new QAction( tr( "User Guide" ), mIface->mainWindow() );
  guide->setObjectName( QStringLiteral( "mActionGeoStationUserGuide" ) );
  guide->setToolTip( tr( "Open GeoStation's user guide in the web browser: getting started, each tool, each Processing algorithm" ) );
  connect( guide, &QAction::triggered, this, &GeoStationPlugin::openUserGuide );
  mMenu->addAction( guide );
  mActions << guide;
  updateActions();
}

void GeoStationPlugin::openUserGuide()
{
  const QString url = GeoStationProcessing::userGuidePage( QStringLiteral( "getting-started.html" ) );
  if ( url.isEmpty() )
  {
    mIface->messageBar()->pushWarning( tr( "GeoStation" ), tr( "The user guide is not installed with this build (it needs python3-markdown when building); it is in the docs folder of the source." ) );
    return;
  }
  QDesktopServices::openUrl( QUrl( url ) );
}

void GeoStationPlugin::updateActions()
{
  const bool open = block() != nullptr;
  for ( QAction *action : { mBlockInfoAction, mPickStationAction } )
    if ( action )
      action->setEnabled( open );
}

void GeoStationPlugin::unload()
{
  disconnect( QgsProject::instance(), nullptr, this, nullptr );
  if ( mIface->mapCanvas()->mapTool() == mPickTool )
    mIface->mapCanvas()->unsetMapTool( mPickTool );
  delete mPickTool;
  if ( mIface->mapCanvas()->mapTool() == mReviewTool )
    mIface->mapCanvas()->unsetMapTool( mReviewTool );
  delete mReviewTool;
  delete mOrientationDock;
  delete mRevisionDock;
  delete mReview;
  mReview = nullptr;
  mReviewAction = nullptr;
  delete mDock;
  if ( mOverview )
    mOverview->removeLayers();
  delete mTrace; // waits for a running trace (at most one station)
  mTrace = nullptr;
  delete mController;
  mController = nullptr;
  delete mOverview;
  mOverview = nullptr;
  delete mStore;
  mStore = nullptr;
  delete mSession;
  mSession = nullptr;
  mMultiviewAction = nullptr;
  mPickStationAction = nullptr;
  for ( QAction *action : std::as_const( mActions ) )
    delete action;
  mActions.clear();
  mBlockInfoAction = nullptr;
  delete mAdjustmentMenu;
  delete mMenu;
  delete mToolBar;
  if ( mRegisteredProvider )
    unregisterGeoStationProvider();
  mRegisteredProvider = false;
  setParent( nullptr ); // QGIS deletes the plugin itself after unload()
}

QString GeoStationPlugin::blockSummary( const geostation::Block &block ) const
{
  return tr( "%1: %2, CRS %3" )
         .arg( QString::fromStdString( block.sourceFile.filename().string() ),
               GeoStationBlockInfoDialog::contentsSummary( block ),
               QString::fromStdString( block.crs ) );
}

bool GeoStationPlugin::openBlockFile( const QString &path )
{
  QString error;
  if ( !mSession->openBlock( path, &error ) )
  {
    mIface->messageBar()->pushMessage( tr( "Cannot open the GeoStation block" ), error, Qgis::MessageLevel::Critical );
    return false;
  }
  mIface->messageBar()->pushMessage( tr( "GeoStation block opened" ), blockSummary( *mSession->block() ), Qgis::MessageLevel::Success );
  updateActions();
  writeProject();
  emit blockOpened( path );
  return true;
}

void GeoStationPlugin::openBlock()
{
  QgsSettings settings;
  const QString path = QFileDialog::getOpenFileName( mIface->mainWindow(), tr( "Open GeoStation Block" ), settings.value( sLastBlockDirKey ).toString(),
                       tr( "GeoStation block (*.geostation.json);;JSON (*.json)" ) );
  if ( path.isEmpty() )
    return;
  settings.setValue( sLastBlockDirKey, QFileInfo( path ).absolutePath() );
  openBlockFile( path );
}

void GeoStationPlugin::importBlock()
{
  // geostation:import_block in QGIS' algorithm dialog (Python processing
  // plugin in 3.22); the block it writes is opened in the Multiview and the Overview
  if ( !QgsPythonRunner::isValid()
       || !QgsPythonRunner::run( QStringLiteral( "import processing\n_geostation_import = processing.execAlgorithmDialog('geostation:import_block') or {}" ) ) )
  {
    showAlgorithmDialog( QStringLiteral( "geostation:import_block" ) );
    return;
  }
  QString path;
  if ( !QgsPythonRunner::eval( QStringLiteral( "str(_geostation_import.get('OUTPUT_BLOCK') or '')" ), path ) || path.isEmpty() || !QFileInfo::exists( path ) )
    return; // cancelled, or the import failed and said why in its log
  if ( openBlockFile( path ) )
    showMultiview();
}

void GeoStationPlugin::showBlockInfo()
{
  if ( !block() )
  {
    mIface->messageBar()->pushMessage( tr( "GeoStation" ), tr( "Open a block first (GeoStation ▸ Open Block…)." ), Qgis::MessageLevel::Info );
    return;
  }
  // Modal: the dialog shows the block, which must not change while it is open.
  GeoStationBlockInfoDialog dialog( *block(), mIface->mainWindow() );
  dialog.exec();
}

QVariantMap GeoStationPlugin::dialogDefaults( const QString &algorithmId ) const
{
  QVariantMap defaults;
  const QgsProcessingAlgorithm *algorithm = QgsApplication::processingRegistry()->algorithmById( algorithmId );
  if ( !algorithm || !mSession->hasBlock() )
    return defaults;
  const auto has = [algorithm]( const char *name ) { return algorithm->parameterDefinition( QLatin1String( name ) ) != nullptr; };
  if ( has( "BLOCK" ) )
    defaults.insert( QStringLiteral( "BLOCK" ), mSession->blockPath() );
  // the images of the Multiview's views: the first for an algorithm of one image, the first two for a pair
  QStringList shown;
  for ( const QString &image : mSession->viewImages() )
    if ( !image.isEmpty() )
      shown << image;
  if ( has( "IMAGE" ) && !shown.isEmpty() )
    defaults.insert( QStringLiteral( "IMAGE" ), shown.at( 0 ) );
  if ( has( "LEFT" ) && has( "RIGHT" ) && shown.size() >= 2 )
  {
    defaults.insert( QStringLiteral( "LEFT" ), shown.at( 0 ) );
    defaults.insert( QStringLiteral( "RIGHT" ), shown.at( 1 ) );
  }
  return defaults;
}

void GeoStationPlugin::showAlgorithmDialog( const QString &algorithmId )
{
  // The algorithm dialog of QGIS 3.22 lives in the Python processing plugin. It starts with the open block
  // and the Multiview's images filled in (as JSON, hex-encoded: a path may hold any character).
  const QByteArray defaults = QJsonDocument( QJsonObject::fromVariantMap( dialogDefaults( algorithmId ) ) ).toJson( QJsonDocument::Compact ).toHex();
  if ( QgsPythonRunner::isValid() &&
       QgsPythonRunner::run( QStringLiteral( "import json, processing\nprocessing.execAlgorithmDialog('%1', json.loads(bytes.fromhex('%2').decode('utf-8')))" )
                             .arg( algorithmId, QString::fromLatin1( defaults ) ) ) )
    return;
  mIface->messageBar()->pushMessage( tr( "GeoStation" ), tr( "Open %1 from the Processing Toolbox (GeoStation)." ).arg( algorithmId ), Qgis::MessageLevel::Info );
}

void GeoStationPlugin::showMultiview()
{
  if ( !mDock )
  {
    mDock = new GeoStationMultiviewDock( mSession, mController, mStore, mIface->mainWindow(), mTrace );
    mIface->addDockWidget( Qt::RightDockWidgetArea, mDock );
  }
  mDock->setUserVisible( true );
  mDock->raise();
}

QObject *GeoStationPlugin::multiviewDock() const
{
  return mDock;
}

void GeoStationPlugin::showOrientation()
{
  showMultiview();
  if ( !mOrientationDock )
  {
    mOrientationDock = new GeoStationOrientationDock( mSession, mDock, mIface->mapCanvas(), mIface->mainWindow() );
    mIface->addDockWidget( Qt::BottomDockWidgetArea, mOrientationDock );
    connect( mOrientationDock, &GeoStationOrientationDock::messageShown, this, [this]( const QString &text, bool warning )
    {
      if ( warning )
        mIface->messageBar()->pushWarning( tr( "GeoStation" ), text );
    } );
  }
  mOrientationDock->setUserVisible( true );
  mOrientationDock->raise();
}

void GeoStationPlugin::showRevisionReview()
{
  if ( !mRevisionDock )
  {
    mRevisionDock = new GeoStationRevisionDock( mIface->mapCanvas(), mIface->mainWindow() );
    mIface->addDockWidget( Qt::RightDockWidgetArea, mRevisionDock );
    connect( mRevisionDock, &GeoStationRevisionDock::message, this, [this]( const QString &text, bool warning )
    {
      mIface->messageBar()->pushMessage( tr( "GeoStation review" ), text, warning ? Qgis::MessageLevel::Warning : Qgis::MessageLevel::Success, 4 );
    } );
    // the change in the images: the Multiview opened for it when a block is open
    connect( mRevisionDock, &GeoStationRevisionDock::changeSelected, this, [this]( const QgsGeometry &oldCourse, const QgsGeometry &newCourse, const QgsCoordinateReferenceSystem &crs )
    {
      if ( !mSession->hasBlock() )
        return;
      showMultiview();
      mDock->showChange( oldCourse, newCourse, crs );
    } );
  }
  mRevisionDock->setUserVisible( true );
  mRevisionDock->raise();
}

void GeoStationPlugin::addPhoto()
{
  GeoStationAddPhotoDialog dialog( mSession->block(), QgsProject::instance()->crs(), mIface->mainWindow() );
  geostation::Camera camera;
  QString error;
  if ( dialog.exec() == QDialog::Accepted && dialog.camera( &camera, &error ) )
    openAddedPhoto( GeoStationAddPhotoDialog::addToBlock( mSession, dialog.photoPath(), camera, dialog.newBlockPath(), dialog.crs(), &error ), error );
}

QString GeoStationPlugin::addPhotoFile( const QString &photoPath, const QString &newBlockPath, const QString &cameraJson )
{
  geostation::Camera camera;
  QString error;
  if ( !GeoStationAddPhotoDialog::cameraForPhoto( mSession->block(), photoPath, cameraJson, &camera, &error ) )
    return openAddedPhoto( QString(), error );
  return openAddedPhoto( GeoStationAddPhotoDialog::addToBlock( mSession, photoPath, camera, newBlockPath, QgsProject::instance()->crs(), &error ), error );
}

QString GeoStationPlugin::openAddedPhoto( const QString &imageId, const QString &error )
{
  if ( imageId.isEmpty() )
  {
    mIface->messageBar()->pushMessage( tr( "GeoStation" ), error, Qgis::MessageLevel::Critical );
    return QString();
  }
  updateActions();
  writeProject();
  showOrientation();
  mOrientationDock->setImage( imageId );
  return imageId;
}

QObject *GeoStationPlugin::orientationDock() const
{
  return mOrientationDock;
}

void GeoStationPlugin::editFeatureClasses()
{
  GeoStationFeatureClassDialog dialog( mSession->featureClasses(), mIface->mainWindow() );
  if ( dialog.exec() == QDialog::Accepted )
  {
    mSession->setFeatureClasses( dialog.classes() );
    writeProject();
  }
}

void GeoStationPlugin::editMeasurementSettings()
{
  GeoStationMeasurementSettingsDialog dialog( mSession, mStore, mIface->mainWindow() );
  if ( dialog.exec() == QDialog::Accepted )
    writeProject();
}

void GeoStationPlugin::goToCoordinate()
{
  if ( !block() )
  {
    mIface->messageBar()->pushMessage( tr( "GeoStation" ), tr( "Open a block first (GeoStation ▸ Open Block…)." ), Qgis::MessageLevel::Info );
    return;
  }
  bool ok = false;
  const QString text = QInputDialog::getText( mIface->mainWindow(), tr( "Go to Coordinate" ),
                       tr( "X Y in %1, a station id or a time (ISO 8601):" ).arg( QString::fromStdString( block()->crs ) ), QLineEdit::Normal, QString(), &ok );
  if ( !ok || text.trimmed().isEmpty() )
    return;
  const QStringList parts = text.simplified().replace( ',', ' ' ).split( ' ', Qt::SkipEmptyParts );
  bool okX = false, okY = false;
  if ( parts.size() == 2 )
  {
    const double x = parts[0].toDouble( &okX ), y = parts[1].toDouble( &okY );
    if ( okX && okY && goToCoordinateXY( x, y ) )
      return;
  }
  const int index = mSession->run().indexOfIdOrTime( text.trimmed().toStdString() );
  if ( index < 0 )
  {
    mIface->messageBar()->pushMessage( tr( "GeoStation" ), tr( "“%1” is neither X Y, a station id nor a time." ).arg( text ), Qgis::MessageLevel::Warning );
    return;
  }
  mSession->setCurrentStation( index );
  showMultiview();
}

bool GeoStationPlugin::goToCoordinateXY( double x, double y )
{
  const int index = mSession->run().indexNearest( Eigen::Vector2d( x, y ) );
  if ( index < 0 )
    return false;
  mSession->setCurrentStation( index );
  showMultiview();
  return true;
}

bool GeoStationPlugin::setFeatureClassesJson( const QString &json )
{
  QList<GeoStationFeatureClass> classes;
  QString error;
  if ( !GeoStationFeatureClass::fromJson( json, classes, &error ) )
  {
    mIface->messageBar()->pushMessage( tr( "GeoStation feature classes" ), error, Qgis::MessageLevel::Critical );
    return false;
  }
  mSession->setFeatureClasses( classes );
  writeProject();
  return true;
}

void GeoStationPlugin::setCurrentClass( const QString &name )
{
  mSession->setCurrentClass( name );
}

bool GeoStationPlugin::setTargetGeoPackage( const QString &path )
{
  QString error;
  if ( !mStore->setTarget( path, &error ) )
  {
    mIface->messageBar()->pushMessage( tr( "GeoStation" ), error, Qgis::MessageLevel::Critical );
    return false;
  }
  writeProject();
  return true;
}

void GeoStationPlugin::setDemLayer( const QString &layerId )
{
  mSession->setDemLayerId( layerId );
}

void GeoStationPlugin::writeProject()
{
  if ( mSession )
    mSession->writeToProject( QgsProject::instance() );
}

void GeoStationPlugin::readProject()
{
  QString error;
  if ( !mSession->readFromProject( QgsProject::instance(), &error ) )
    return;
  if ( !error.isEmpty() )
    mIface->messageBar()->pushMessage( tr( "GeoStation session" ), error, Qgis::MessageLevel::Warning );
  updateActions();
  if ( mSession->block() )
    showMultiview();
}

// ---- the entry points QGIS looks for in a C++ plugin ----

QGISEXTERN QgisPlugin *classFactory( QgisInterface *iface )
{
  return new GeoStationPlugin( iface );
}

QGISEXTERN const QString *name()
{
  return &sName;
}

QGISEXTERN const QString *description()
{
  return &sDescription;
}

QGISEXTERN const QString *category()
{
  return &sCategory;
}

QGISEXTERN int type()
{
  return sPluginType;
}

QGISEXTERN const QString *version()
{
  return &sVersion;
}

QGISEXTERN const QString *icon()
{
  return &sIcon;
}

QGISEXTERN void unload( QgisPlugin *plugin )
{
  delete plugin;
}

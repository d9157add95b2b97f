/***************************************************************************
  geostationplugin.cpp - the GeoStation plugin for QGIS desktop
 ***************************************************************************/
#include "geostationplugin.h"

#include <QAction>
#include <QFileDialog>
#include <QFileInfo>
#include <QMainWindow>
#include <QMenu>
#include <QMenuBar>
#include <QToolBar>

#include <qgisinterface.h>
#include <qgsmessagebar.h>
#include <qgspythonrunner.h>
#include <qgssettings.h>

#include "blockinfodialog.h"
#include "geostationprovider.h"
#include "io/block.h"

namespace
{
  const QString sName = QStringLiteral( "GeoStation" );
  const QString sDescription = QStringLiteral( "Softcopy photogrammetry: multiview measurement, monoplotting and road tracing from oriented imagery" );
  const QString sCategory = QStringLiteral( "Plugins" );
  const QString sVersion = QStringLiteral( "0.1.0" );
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
  mBlockInfoAction = addAction( QStringLiteral( "mActionGeoStationBlockInfo" ), QStringLiteral( ":/geostation/icons/blockinfo.svg" ), tr( "Block Information…" ),
                                tr( "Show the cameras (interior orientation), stations and images of the open block" ), &GeoStationPlugin::showBlockInfo );
  QAction *project = addAction( QStringLiteral( "mActionGeoStationProjectToImage" ), QStringLiteral( ":/geostation/icons/projecttoimage.svg" ), tr( "Project Map Points to Image…" ),
                                tr( "Find where map points with heights appear in an oriented image" ), nullptr );
  connect( project, &QAction::triggered, this, [this] { showAlgorithmDialog( QStringLiteral( "geostation:project_to_image" ) ); } );

  addAlgorithmAction( mMenu, QStringLiteral( "mActionGeoStationMonoplot" ), tr( "Monoplot Image Features onto a DEM…" ), QStringLiteral( "geostation:monoplot" ) );

  mAdjustmentMenu = mMenu->addMenu( tr( "Adjustment" ) );
  mAdjustmentMenu->setObjectName( QStringLiteral( "mGeoStationAdjustmentMenu" ) );
  addAlgorithmAction( mAdjustmentMenu, QStringLiteral( "mActionGeoStationIntersect" ), tr( "Intersect Image Points…" ), QStringLiteral( "geostation:intersect" ) );
  addAlgorithmAction( mAdjustmentMenu, QStringLiteral( "mActionGeoStationResection" ), tr( "Space Resection…" ), QStringLiteral( "geostation:resection" ) );
  addAlgorithmAction( mAdjustmentMenu, QStringLiteral( "mActionGeoStationBundleAdjust" ), tr( "Bundle Adjustment…" ), QStringLiteral( "geostation:bundle_adjust" ) );
  addAlgorithmAction( mAdjustmentMenu, QStringLiteral( "mActionGeoStationInnerOrientation" ), tr( "Inner Orientation from Fiducials…" ), QStringLiteral( "geostation:inner_orientation" ) );
  updateActions();
}

void GeoStationPlugin::updateActions()
{
  if ( mBlockInfoAction )
    mBlockInfoAction->setEnabled( static_cast<bool>( mBlock ) );
}

void GeoStationPlugin::unload()
{
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
  mBlock.reset();
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
  try
  {
    auto block = std::make_unique<geostation::Block>( geostation::Block::load( path.toStdString() ) );
    mIface->messageBar()->pushMessage( tr( "GeoStation block opened" ), blockSummary( *block ), Qgis::MessageLevel::Success );
    mBlock = std::move( block );
    updateActions();
    emit blockOpened( path );
    return true;
  }
  catch ( const std::exception &e )
  {
    mIface->messageBar()->pushMessage( tr( "Cannot open the GeoStation block" ), QString::fromStdString( e.what() ), Qgis::MessageLevel::Critical );
    return false;
  }
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

void GeoStationPlugin::showBlockInfo()
{
  if ( !mBlock )
  {
    mIface->messageBar()->pushMessage( tr( "GeoStation" ), tr( "Open a block first (GeoStation ▸ Open Block…)." ), Qgis::MessageLevel::Info );
    return;
  }
  // Modal: the dialog shows mBlock, which must not change while it is open.
  GeoStationBlockInfoDialog dialog( *mBlock, mIface->mainWindow() );
  dialog.exec();
}

void GeoStationPlugin::showAlgorithmDialog( const QString &algorithmId )
{
  // The algorithm dialog of QGIS 3.22 lives in the Python processing plugin.
  if ( QgsPythonRunner::isValid() && QgsPythonRunner::run( QStringLiteral( "import processing\nprocessing.execAlgorithmDialog('%1')" ).arg( algorithmId ) ) )
    return;
  mIface->messageBar()->pushMessage( tr( "GeoStation" ), tr( "Open %1 from the Processing Toolbox (GeoStation)." ).arg( algorithmId ), Qgis::MessageLevel::Info );
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

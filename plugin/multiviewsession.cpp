/***************************************************************************
  multiviewsession.cpp
 ***************************************************************************/
#include "multiviewsession.h"

#include <QDateTime>
#include <QDir>
#include <QFileInfo>

#include <qgsproject.h>

namespace
{
  const QString sScope = QStringLiteral( "GeoStation" );
}

GeoStationMultiviewSession::GeoStationMultiviewSession( QObject *parent )
  : QObject( parent )
{
  for ( int i = 0; i < 3; ++i )
    mViews << ViewAssignment();
  // a writer may replace the file in steps (temporary file, rename): read it once it has settled
  mReloadTimer.setSingleShot( true );
  mReloadTimer.setInterval( 500 );
  connect( &mReloadTimer, &QTimer::timeout, this, [this] { reloadBlock(); } );
  const auto changed = [this]
  {
    watchBlockFile();
    if ( mBlock && blockFileStamp() != mLoadedStamp )
      mReloadTimer.start();
  };
  connect( &mWatcher, &QFileSystemWatcher::fileChanged, this, changed );
  connect( &mWatcher, &QFileSystemWatcher::directoryChanged, this, changed );
}

std::map<std::string, geostation::OrientedImage> GeoStationMultiviewSession::orientedImages( const geostation::Block &block )
{
  std::map<std::string, geostation::OrientedImage> oriented;
  for ( const geostation::BlockImage &image : block.images )
  {
    if ( !image.exterior )
      continue;
    try
    {
      oriented.emplace( image.id, block.orientedImage( image ) );
    }
    catch ( const std::exception & )
    {
      // not usable for measuring (e.g. scan affine without pixel size): shown, not measured
    }
  }
  return oriented;
}

void GeoStationMultiviewSession::adoptBlock( std::unique_ptr<geostation::Block> block )
{
  mOriented = orientedImages( *block );
  mBlock = std::move( block );
  mCrs = QgsCoordinateReferenceSystem();
  mCrs.createFromUserInput( QString::fromStdString( mBlock->crs ) );
  mRun = geostation::StationSequence( *mBlock );
}

QString GeoStationMultiviewSession::blockFileStamp() const
{
  const QFileInfo file( mBlockPath );
  return file.exists() ? QStringLiteral( "%1 %2" ).arg( file.size() ).arg( file.lastModified().toMSecsSinceEpoch() ) : QString();
}

void GeoStationMultiviewSession::watchBlockFile()
{
  if ( !mWatcher.files().isEmpty() )
    mWatcher.removePaths( mWatcher.files() );
  if ( !mWatcher.directories().isEmpty() )
    mWatcher.removePaths( mWatcher.directories() );
  if ( mBlockPath.isEmpty() )
    return;
  if ( QFileInfo::exists( mBlockPath ) )
    mWatcher.addPath( mBlockPath );
  mWatcher.addPath( QFileInfo( mBlockPath ).absolutePath() );
}

bool GeoStationMultiviewSession::reloadBlock()
{
  if ( !mBlock )
    return false;
  std::unique_ptr<geostation::Block> block;
  try
  {
    block = std::make_unique<geostation::Block>( geostation::Block::load( mBlockPath.toStdString() ) );
  }
  catch ( const std::exception &e )
  {
    emit blockFileProblem( tr( "The block file %1 changed on disk but cannot be read now (%2); measuring goes on with the block as it was loaded." )
                           .arg( mBlockPath, QString::fromStdString( e.what() ) ) );
    return false;
  }
  mLoadedStamp = blockFileStamp();
  if ( block->toJsonText() == mBlock->toJsonText() )
    return true;

  int newOrientations = 0;
  for ( const geostation::BlockImage &image : block->images )
  {
    const geostation::BlockImage *old = mBlock->findImage( image.id );
    const bool same = old && old->exterior.has_value() == image.exterior.has_value() &&
                      ( !image.exterior || ( old->exterior->projectionCentre == image.exterior->projectionCentre && old->exterior->omegaDeg == image.exterior->omegaDeg &&
                                             old->exterior->phiDeg == image.exterior->phiDeg && old->exterior->kappaDeg == image.exterior->kappaDeg ) );
    newOrientations += same ? 0 : 1;
  }
  const QString stationId = currentStationId();
  adoptBlock( std::move( block ) );
  const int index = mRun.indexOf( stationId.toStdString() );
  mCurrent = mRun.empty() ? -1 : std::max( 0, index );
  // the views stay on their cameras where the block still has them
  bool camerasKept = true;
  for ( const ViewAssignment &view : std::as_const( mViews ) )
    camerasKept = camerasKept && ( view.cameraId.isEmpty() || mBlock->findCamera( view.cameraId.toStdString() ) );
  if ( !camerasKept )
    resetViews();
  emit blockReloaded( tr( "The block file %1 changed on disk and was read again: %n image(s) have another orientation; points measured from now on use it.", nullptr, newOrientations )
                      .arg( QFileInfo( mBlockPath ).fileName() ) );
  emit stationChanged( mCurrent );
  emit viewImagesChanged();
  return true;
}

bool GeoStationMultiviewSession::openBlock( const QString &path, QString *error )
{
  std::unique_ptr<geostation::Block> block;
  try
  {
    block = std::make_unique<geostation::Block>( geostation::Block::load( path.toStdString() ) );
  }
  catch ( const std::exception &e )
  {
    if ( error )
      *error = QString::fromStdString( e.what() );
    return false;
  }
  adoptBlock( std::move( block ) );
  mBlockPath = QFileInfo( path ).absoluteFilePath();
  mLoadedStamp = blockFileStamp();
  watchBlockFile();
  mCurrent = mRun.empty() ? -1 : 0;
  resetViews();
  if ( mTarget.isEmpty() )
    mTarget = defaultTargetGeoPackage();
  emit blockChanged();
  emit targetChanged();
  emit stationChanged( mCurrent );
  emit viewImagesChanged();
  return true;
}

void GeoStationMultiviewSession::closeBlock()
{
  mBlock.reset();
  mOriented.clear();
  mBlockPath.clear();
  mReloadTimer.stop();
  watchBlockFile();
  mCrs = QgsCoordinateReferenceSystem();
  mRun = geostation::StationSequence();
  mCurrent = -1;
  emit blockChanged();
  emit stationChanged( mCurrent );
  emit viewImagesChanged();
}

void GeoStationMultiviewSession::resetViews()
{
  // one view per image of the first station (at most six); without stations, the views there were (at least two)
  int n = std::max<int>( mViews.size(), 2 );
  if ( !mRun.empty() )
    n = std::clamp<int>( static_cast<int>( mRun.at( 0 ).imageIds.size() ), 1, sMaxViews );
  mViews.clear();
  for ( int i = 0; i < n; ++i )
    mViews << ViewAssignment();
  if ( !mBlock || mRun.empty() )
    return;
  const geostation::SequenceStation &station = mRun.at( std::max( 0, mCurrent ) );
  for ( int i = 0; i < n && i < static_cast<int>( station.imageIds.size() ); ++i )
    mViews[i].cameraId = QString::fromStdString( mBlock->image( station.imageIds[i] ).cameraId );
}

QString GeoStationMultiviewSession::currentStationId() const
{
  return mCurrent >= 0 && mCurrent < mRun.size() ? QString::fromStdString( mRun.at( mCurrent ).id ) : QString();
}

void GeoStationMultiviewSession::setCurrentStation( int index )
{
  if ( mRun.empty() )
    return;
  index = std::clamp( index, 0, mRun.size() - 1 );
  if ( index == mCurrent )
    return;
  mCurrent = index;
  emit stationChanged( mCurrent );
  emit viewImagesChanged();
}

void GeoStationMultiviewSession::setViewCount( int count )
{
  count = std::clamp( count, 1, sMaxViews );
  if ( count == mViews.size() )
    return;
  while ( mViews.size() > count )
    mViews.removeLast();
  while ( mViews.size() < count )
    mViews << ViewAssignment();
  emit viewImagesChanged();
}

bool GeoStationMultiviewSession::setViewImage( int view, const QString &imageId )
{
  if ( !mBlock || view < 0 || view >= mViews.size() )
    return false;
  const geostation::BlockImage *image = mBlock->findImage( imageId.toStdString() );
  if ( !image )
    return false;
  ViewAssignment a;
  a.cameraId = QString::fromStdString( image->cameraId );
  const int station = mRun.indexOf( image->stationId.empty() ? image->id : image->stationId );
  a.stationOffset = station >= 0 && mCurrent >= 0 ? station - mCurrent : 0;
  mViews[view] = a;
  emit viewImagesChanged();
  return true;
}

QString GeoStationMultiviewSession::imageFor( const ViewAssignment &assignment, int viewIndex ) const
{
  if ( !mBlock || mCurrent < 0 )
    return QString();
  const int index = mCurrent + assignment.stationOffset;
  if ( index < 0 || index >= mRun.size() )
    return QString();
  const geostation::SequenceStation &station = mRun.at( index );
  if ( !assignment.cameraId.isEmpty() )
  {
    for ( const std::string &id : station.imageIds )
      if ( mBlock->image( id ).cameraId == assignment.cameraId.toStdString() )
        return QString::fromStdString( id );
    return QString();
  }
  return viewIndex < static_cast<int>( station.imageIds.size() ) ? QString::fromStdString( station.imageIds[viewIndex] ) : QString();
}

QStringList GeoStationMultiviewSession::viewImages() const
{
  QStringList ids;
  for ( int i = 0; i < mViews.size(); ++i )
    ids << imageFor( mViews[i], i );
  return ids;
}

const geostation::OrientedImage *GeoStationMultiviewSession::orientedImage( const QString &imageId ) const
{
  auto it = mOriented.find( imageId.toStdString() );
  return it == mOriented.end() ? nullptr : &it->second;
}

QString GeoStationMultiviewSession::imagePath( const QString &imageId ) const
{
  const geostation::BlockImage *image = mBlock ? mBlock->findImage( imageId.toStdString() ) : nullptr;
  return image ? QString::fromStdString( mBlock->imageFilePath( *image ).string() ) : QString();
}

QString GeoStationMultiviewSession::imageStation( const QString &imageId ) const
{
  const geostation::BlockImage *image = mBlock ? mBlock->findImage( imageId.toStdString() ) : nullptr;
  return image ? QString::fromStdString( image->stationId ) : QString();
}

QString GeoStationMultiviewSession::imageTime( const QString &imageId ) const
{
  const geostation::BlockImage *image = mBlock ? mBlock->findImage( imageId.toStdString() ) : nullptr;
  const geostation::Station *station = image && !image->stationId.empty() ? mBlock->findStation( image->stationId ) : nullptr;
  return station ? QString::fromStdString( station->time ) : QString();
}

void GeoStationMultiviewSession::setFeatureClasses( const QList<GeoStationFeatureClass> &classes )
{
  mClasses = classes;
  if ( !findClass( mCurrentClass ) )
    mCurrentClass = mClasses.isEmpty() ? QString() : mClasses.first().name;
  emit featureClassesChanged();
}

void GeoStationMultiviewSession::setCurrentClass( const QString &name )
{
  if ( !findClass( name ) || name == mCurrentClass )
    return;
  mCurrentClass = name;
  emit featureClassesChanged();
}

const GeoStationFeatureClass *GeoStationMultiviewSession::findClass( const QString &name ) const
{
  for ( const GeoStationFeatureClass &c : mClasses )
    if ( c.name == name )
      return &c;
  return nullptr;
}

void GeoStationMultiviewSession::setTargetGeoPackage( const QString &path )
{
  const QString absolute = path.isEmpty() ? QString() : QFileInfo( path ).absoluteFilePath();
  if ( absolute == mTarget )
    return;
  mTarget = absolute;
  emit targetChanged();
}

QString GeoStationMultiviewSession::defaultTargetGeoPackage() const
{
  return mBlockPath.isEmpty() ? QString() : QFileInfo( mBlockPath ).absoluteDir().filePath( QStringLiteral( "measurements.gpkg" ) );
}

void GeoStationMultiviewSession::setDemLayerId( const QString &layerId )
{
  mDemLayerId = layerId;
  emit settingsChanged();
}

void GeoStationMultiviewSession::setRoadPlane( double cameraHeightAboveRoadM, double sigmaM )
{
  mCameraHeight = cameraHeightAboveRoadM;
  mRoadSigma = std::max( 0.0, sigmaM );
  emit settingsChanged();
}

void GeoStationMultiviewSession::writeToProject( QgsProject *project ) const
{
  const QgsPathResolver resolver = project->pathResolver();
  project->writeEntry( sScope, QStringLiteral( "block" ), mBlockPath.isEmpty() ? QString() : resolver.writePath( mBlockPath ) );
  project->writeEntry( sScope, QStringLiteral( "station" ), currentStationId() );
  QStringList views;
  for ( const ViewAssignment &a : mViews )
    views << QStringLiteral( "%1@%2" ).arg( a.cameraId ).arg( a.stationOffset );
  project->writeEntry( sScope, QStringLiteral( "views" ), views );
  project->writeEntry( sScope, QStringLiteral( "featureClasses" ), GeoStationFeatureClass::toJson( mClasses ) );
  project->writeEntry( sScope, QStringLiteral( "currentClass" ), mCurrentClass );
  project->writeEntry( sScope, QStringLiteral( "target" ), mTarget.isEmpty() ? QString() : resolver.writePath( mTarget ) );
  project->writeEntry( sScope, QStringLiteral( "demLayer" ), mDemLayerId );
  project->writeEntry( sScope, QStringLiteral( "cameraHeightAboveRoad" ), mCameraHeight );
  project->writeEntry( sScope, QStringLiteral( "roadPlaneSigma" ), mRoadSigma );
}

bool GeoStationMultiviewSession::readFromProject( QgsProject *project, QString *error )
{
  bool present = false;
  const QString blockEntry = project->readEntry( sScope, QStringLiteral( "block" ), QString(), &present );
  if ( !present )
    return false;
  const QgsPathResolver resolver = project->pathResolver();
  QList<GeoStationFeatureClass> classes;
  QString classError;
  if ( GeoStationFeatureClass::fromJson( project->readEntry( sScope, QStringLiteral( "featureClasses" ), QStringLiteral( "[]" ) ), classes, &classError ) )
    setFeatureClasses( classes );
  else if ( error )
    *error = classError;
  setCurrentClass( project->readEntry( sScope, QStringLiteral( "currentClass" ) ) );
  const QString target = project->readEntry( sScope, QStringLiteral( "target" ) );
  mTarget = target.isEmpty() ? QString() : resolver.readPath( target );
  mDemLayerId = project->readEntry( sScope, QStringLiteral( "demLayer" ) );
  mCameraHeight = project->readDoubleEntry( sScope, QStringLiteral( "cameraHeightAboveRoad" ), 2.6 );
  mRoadSigma = project->readDoubleEntry( sScope, QStringLiteral( "roadPlaneSigma" ), 0.05 );
  emit targetChanged();
  emit settingsChanged();
  if ( blockEntry.isEmpty() )
  {
    closeBlock();
    return true;
  }
  QString blockError;
  if ( !openBlock( resolver.readPath( blockEntry ), &blockError ) )
  {
    if ( error )
      *error = blockError;
    return true;
  }
  QList<ViewAssignment> views;
  for ( const QString &v : project->readListEntry( sScope, QStringLiteral( "views" ) ) )
  {
    const int at = v.lastIndexOf( '@' );
    ViewAssignment a;
    a.cameraId = v.left( at );
    a.stationOffset = at >= 0 ? v.mid( at + 1 ).toInt() : 0;
    views << a;
  }
  if ( !views.isEmpty() )
    mViews = views.mid( 0, sMaxViews );
  const int station = mRun.indexOf( project->readEntry( sScope, QStringLiteral( "station" ) ).toStdString() );
  if ( station >= 0 )
    mCurrent = station;
  emit stationChanged( mCurrent );
  emit viewImagesChanged();
  return true;
}

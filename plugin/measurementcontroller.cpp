/***************************************************************************
  measurementcontroller.cpp
 ***************************************************************************/
#include "measurementcontroller.h"

#include <QDateTime>
#include <QElapsedTimer>
#include <QUuid>

#include <qgsproject.h>
#include <qgsrasterlayer.h>

#include "dem/dem.h"
#include "dem/demintersection.h"
#include "dem/monoplotter.h"
#include "geometry/crs.h"
#include "multiviewsession.h"
#include "workstation/measurementwindows.h"

GeoStationMeasurementController::GeoStationMeasurementController( GeoStationMultiviewSession *session, GeoStationMeasurementStore *store, QObject *parent )
  : QObject( parent )
  , mSession( session )
  , mStore( store )
{
  mOptions.area.minScore = 0.7;
}

GeoStationMeasurementController::~GeoStationMeasurementController() = default;

void GeoStationMeasurementController::prefetch( const QStringList &imageIds )
{
  std::vector<std::string> paths;
  for ( const QString &id : imageIds )
  {
    const std::string path = mSession->imagePath( id ).toStdString();
    if ( !path.empty() && !mCache->contains( path ) )
      paths.push_back( path );
  }
  // instead of what an earlier station asked for and has not started: get() from the GUI waits for a load in progress
  mPrefetcher.prefetch( paths );
}

void GeoStationMeasurementController::resetViews()
{
  const QStringList ids = mSession->viewImages();
  mViews = QVector<ViewState>( ids.size() );
  for ( int i = 0; i < ids.size(); ++i )
    mViews[i].imageId = ids[i];
  mReference = -1;
}

void GeoStationMeasurementController::viewsChanged()
{
  resetViews();
  emit viewStatesChanged();
}

void GeoStationMeasurementController::pick( int view, const QPointF &pixelInImage )
{
  if ( mViews.size() != mSession->viewCount() || ( view < mViews.size() && mViews[view].imageId != mSession->viewImages().value( view ) ) )
    resetViews();
  if ( view < 0 || view >= mViews.size() || mViews[view].imageId.isEmpty() )
    return;

  if ( mReference >= 0 && view != mReference )
  {
    // the operator's own point in this view
    ViewState &s = mViews[view];
    s.observed = true;
    s.corrected = true;
    s.pixel = pixelInImage;
    s.sigmaPx = 0.5;
    s.status = s.curve.pieces.empty() ? tr( "set by hand" )
               : tr( "set by hand, %1 px from the epipolar curve" ).arg( s.curve.distanceToCurvePx( Eigen::Vector2d( pixelInImage.x(), pixelInImage.y() ) ), 0, 'f', 1 );
    emit viewStatesChanged();
    return;
  }

  if ( !mSession->findClass( mSession->currentClass() ) )
  {
    emit message( tr( "Define a feature class to measure (GeoStation ▸ Feature Classes…)." ), true );
    return;
  }
  QString problem;
  if ( mFeature.vertices.isEmpty() && !mStore->checkWritable( &problem ) )
  {
    emit message( problem, true );
    return;
  }
  const QString referenceId = mViews[view].imageId;
  if ( !mSession->orientedImage( referenceId ) )
  {
    emit message( tr( "%1 is not oriented: it cannot be measured in (orient it by resection or bundle adjustment)." ).arg( referenceId ), true );
    return;
  }

  QElapsedTimer timer;
  timer.start();
  resetViews();
  mReference = view;
  // the correlation window's shape predicted from the surface the point lies on: the DEM layer, or the road plane
  geostation::ProposalOptions options = mOptions;
  QString demProblem;
  const bool onDem = loadDem( &demProblem );
  if ( onDem )
    options.groundOfPixel = geostation::demGroundOfPixel( *mDem, *mBlockToDem );
  else
  {
    const double roadZ = mSession->orientedImage( referenceId )->exterior().projectionCentre.z() - mSession->cameraHeightAboveRoadM();
    options.groundOfPixel = [roadZ]( const geostation::OrientedImage & image, const Eigen::Vector2d & pixel ) { return geostation::roadPlanePoint( image, pixel, roadZ ); };
  }
  std::vector<std::shared_ptr<const geostation::MatchImage>> pixels( mViews.size() );
  std::vector<geostation::MeasurementView> views( mViews.size() );
  std::vector<geostation::MatchImageCache::Entry> entries( mViews.size() );
  QVector<QString> unreadable( mViews.size() ); // why a view's image cannot be read (deleted, moved, corrupt), empty if it can
  bool windowsNeeded = false;
  for ( int i = 0; i < mViews.size(); ++i )
  {
    views[i].imageId = mViews[i].imageId.toStdString();
    views[i].image = mSession->orientedImage( mViews[i].imageId );
    const QString path = mSession->imagePath( mViews[i].imageId );
    if ( !path.isEmpty() )
    {
      entries[i] = mCache->get( path.toStdString() );
      unreadable[i] = QString::fromStdString( entries[i].message );
      windowsNeeded = windowsNeeded || entries[i].needsWindow;
    }
  }
  // images too large to prepare whole: the windows this click's matching reads
  if ( windowsNeeded )
  {
    std::vector<cv::Size> sizes( mViews.size() );
    for ( int i = 0; i < mViews.size(); ++i )
      sizes[i] = entries[i].imageSize;
    const geostation::MeasurementWindowSummary windows = geostation::measurementWindows( views, sizes, view, Eigen::Vector2d( pixelInImage.x(), pixelInImage.y() ),
        options, mCache->maxWholePixels() );
    for ( int i = 0; i < mViews.size(); ++i )
      if ( entries[i].needsWindow && windows.windows[i] )
        entries[i] = mCache->get( mSession->imagePath( mViews[i].imageId ).toStdString(), *windows.windows[i] );
    if ( !windows.cut.empty() )
      emit message( tr( "The image of view %1 is too large to search along the whole epipolar line: searched around the point on the %2 only." )
                    .arg( windows.cut.front() + 1 ).arg( onDem ? tr( "DEM" ) : tr( "road plane" ) ), false );
  }
  for ( int i = 0; i < mViews.size(); ++i )
  {
    pixels[i] = entries[i].image;
    views[i].pixels = pixels[i].get();
  }
  for ( int i = 0; i < mViews.size(); ++i )
    if ( !unreadable[i].isEmpty() )
    {
      emit message( tr( "The image of view %1 (%2) cannot be read, so no point is proposed %3: %4. Put the file back, or measure there by hand." )
                    .arg( i + 1 ).arg( mViews[i].imageId, i == view ? tr( "from it" ) : tr( "in it" ), unreadable[i] ), true );
      break;
    }
  const std::vector<geostation::ConjugateProposal> proposals = geostation::proposeConjugates( views, view, Eigen::Vector2d( pixelInImage.x(), pixelInImage.y() ), options );
  for ( int i = 0; i < mViews.size(); ++i )
  {
    ViewState &s = mViews[i];
    if ( i == view )
    {
      s.observed = true;
      s.reference = true;
      s.pixel = pixelInImage;
      s.sigmaPx = 0.5;
      s.status = tr( "reference" );
      continue;
    }
    const geostation::ConjugateProposal &p = proposals[i];
    s.curve = p.curve;
    if ( p.matched() )
    {
      s.proposed = true;
      s.pixel = QPointF( p.pixelInImage.x(), p.pixelInImage.y() );
      s.score = p.score;
      s.sigmaPx = std::max( 0.3, p.sigmaPx );
      // only a least-squares match that passed its checks is taken as it is; a correlation peak is the operator's to confirm
      s.doubtful = p.status != geostation::MatchStatus::Lsm;
      s.observed = !s.doubtful;
      s.status = s.doubtful ? tr( "correlation only %1: click to confirm" ).arg( p.score, 0, 'f', 2 ) : tr( "match %1" ).arg( p.score, 0, 'f', 2 );
    }
    else if ( !unreadable[i].isEmpty() || !unreadable[view].isEmpty() )
      s.status = tr( "no proposal: %1" ).arg( !unreadable[i].isEmpty() ? tr( "its image cannot be read" ) : tr( "the image clicked in cannot be read" ) );
    else if ( !mViews[i].imageId.isEmpty() )
      s.status = tr( "no match (%1): %2" ).arg( QString::fromStdString( geostation::matchStatusName( p.status ) ), QString::fromStdString( p.message ) );
  }
  mLastProposalMs = timer.nsecsElapsed() / 1e6;
  emit viewStatesChanged();
}

bool GeoStationMeasurementController::loadDem( QString *why )
{
  QgsRasterLayer *demLayer = qobject_cast<QgsRasterLayer *>( QgsProject::instance()->mapLayer( mSession->demLayerId() ) );
  if ( !demLayer )
    return false;
  const QString path = demLayer->source();
  // a DEM that could not be opened is not read again on every click
  if ( path == mDemPath && !mDemError.isEmpty() )
  {
    *why = mDemError;
    return false;
  }
  try
  {
    if ( path != mDemPath || !mDem )
    {
      mDemError.clear();
      mDem.reset();
      mBlockToDem.reset();
      mDemPath = path;
      mDem = std::make_unique<geostation::Dem>( path.toStdString() );
      mBlockToDem = std::make_unique<geostation::CrsTransform>( mSession->block()->crs, mDem->crsWkt() );
    }
    return true;
  }
  catch ( const std::exception &e )
  {
    mDem.reset();
    mBlockToDem.reset();
    mDemError = tr( "The DEM %1 cannot be used: %2" ).arg( demLayer->name(), QString::fromStdString( e.what() ) );
    *why = mDemError;
    return false;
  }
}

geostation::MeasuredVertex GeoStationMeasurementController::singleRayVertex( const geostation::VertexObservation &observation, QString *why )
{
  if ( loadDem( why ) )
  {
    try
    {
      const geostation::Monoplotter monoplotter( *observation.image, *mDem, *mBlockToDem );
      return geostation::demVertex( observation, monoplotter );
    }
    catch ( const std::exception &e )
    {
      *why = tr( "The DEM cannot be used: %1" ).arg( QString::fromStdString( e.what() ) );
      return geostation::MeasuredVertex();
    }
  }
  if ( !why->isEmpty() )
    return geostation::MeasuredVertex();
  const double roadZ = observation.image->exterior().projectionCentre.z() - mSession->cameraHeightAboveRoadM();
  return geostation::roadPlaneVertex( observation, roadZ, mSession->roadPlaneSigmaM() );
}

bool GeoStationMeasurementController::acceptPoint()
{
  if ( mReference < 0 )
  {
    emit message( tr( "Click the point in one view first." ), true );
    return false;
  }
  std::vector<geostation::VertexObservation> observations;
  QStringList noLongerOriented; // the block file was read again meanwhile, without their orientation
  for ( const ViewState &s : std::as_const( mViews ) )
    if ( s.observed )
    {
      if ( const geostation::OrientedImage *image = mSession->orientedImage( s.imageId ) )
        observations.push_back( { s.imageId.toStdString(), image, Eigen::Vector2d( s.pixel.x(), s.pixel.y() ), s.sigmaPx } );
      else
        noLongerOriented << s.imageId;
    }
  if ( observations.empty() )
  {
    emit message( tr( "%1 is no longer oriented in the block: the point cannot be computed." ).arg( noLongerOriented.join( QLatin1String( ", " ) ) ), true );
    return false;
  }
  geostation::MeasuredVertex vertex;
  QString why;
  if ( observations.size() >= 2 )
    vertex = geostation::intersectVertex( observations );
  else
    vertex = singleRayVertex( observations.front(), &why );
  if ( !vertex.ok() )
  {
    emit message( why.isEmpty() ? tr( "The vertex cannot be computed: %1" ).arg( QString::fromStdString( vertex.message ) ) : why, true );
    return false;
  }
  if ( mFeature.vertices.isEmpty() )
  {
    const QString referenceId = mViews[mReference].imageId;
    mFeature.station = mSession->imageStation( referenceId );
    mFeature.acquired = mSession->imageTime( referenceId );
  }
  // a line or polygon digitised in one image on the DEM follows the terrain between the operator's vertices
  OperatorVertex op;
  if ( vertex.method == geostation::VertexMethod::MonoplotDem && observations.size() == 1 )
  {
    op.demImageId = QString::fromStdString( observations.front().imageId );
    op.pixel = QPointF( observations.front().pixelInImage.x(), observations.front().pixelInImage.y() );
    const GeoStationFeatureClass *lineClass = mSession->findClass( mSession->currentClass() );
    const bool isLine = lineClass && lineClass->geometry != GeoStationFeatureClass::Geometry::Point;
    if ( isLine && !mOperatorVertices.isEmpty() && mOperatorVertices.last().demImageId == op.demImageId && loadDem( &why ) )
    {
      const OperatorVertex &previous = mOperatorVertices.last();
      geostation::VertexObservation from = observations.front();
      from.pixelInImage = Eigen::Vector2d( previous.pixel.x(), previous.pixel.y() );
      const geostation::Monoplotter monoplotter( *from.image, *mDem, *mBlockToDem );
      for ( const geostation::MeasuredVertex &between : geostation::demVerticesBetween( from, observations.front().pixelInImage, monoplotter, sDensifyStepPx ) )
      {
        mFeature.vertices << between;
        ++op.densifiedBefore;
      }
    }
  }
  mOperatorVertices << op;
  mFeature.vertices << vertex;

  QStringList residuals;
  for ( size_t i = 0; i < vertex.imageIds.size() && i < vertex.residualsPx.size(); ++i )
    residuals << QStringLiteral( "%1 %2 px" ).arg( QString::fromStdString( vertex.imageIds[i] ) ).arg( vertex.residualsPx[i].norm(), 0, 'f', 2 );
  QString text = tr( "Vertex %1 (%2, %3 ray(s)): X %4  Y %5  Z %6 m; σ %7 / %8 / %9 m" )
                 .arg( mFeature.vertices.size() )
                 .arg( QString::fromStdString( geostation::vertexMethodName( vertex.method ) ) )
                 .arg( vertex.imageIds.size() )
                 .arg( vertex.point.x(), 0, 'f', 3 ).arg( vertex.point.y(), 0, 'f', 3 ).arg( vertex.point.z(), 0, 'f', 3 )
                 .arg( vertex.sigmaM.x(), 0, 'f', 3 ).arg( vertex.sigmaM.y(), 0, 'f', 3 ).arg( vertex.sigmaM.z(), 0, 'f', 3 );
  if ( vertex.method == geostation::VertexMethod::Intersection )
    text += tr( "; residuals %1; ray angle %2°" ).arg( residuals.join( QLatin1String( ", " ) ) ).arg( vertex.maxRayAngleDeg, 0, 'f', 1 );
  if ( op.densifiedBefore > 0 )
    text += tr( "; %n vertex(es) on the terrain before it", nullptr, op.densifiedBefore );
  emit message( text, false );
  if ( !vertex.message.empty() )
    emit message( QString::fromStdString( vertex.message ), true );

  resetViews();
  emit viewStatesChanged();
  emit featureChanged();
  const GeoStationFeatureClass *featureClass = mSession->findClass( mSession->currentClass() );
  if ( featureClass && featureClass->geometry == GeoStationFeatureClass::Geometry::Point )
    finishFeature();
  return true;
}

void GeoStationMeasurementController::undoVertex()
{
  if ( mReference >= 0 )
  {
    // first the open point, then the vertices
    resetViews();
    emit viewStatesChanged();
    return;
  }
  if ( mFeature.vertices.isEmpty() )
    return;
  // the operator's last vertex, with the vertices that densified the line before it
  const int densified = mOperatorVertices.isEmpty() ? 0 : mOperatorVertices.takeLast().densifiedBefore;
  for ( int k = 0; k <= densified && !mFeature.vertices.isEmpty(); ++k )
    mFeature.vertices.removeLast();
  emit message( tr( "Vertex %1 taken back." ).arg( mFeature.vertices.size() + 1 ), false );
  emit featureChanged();
}

bool GeoStationMeasurementController::finishFeature()
{
  const GeoStationFeatureClass *featureClass = mSession->findClass( mSession->currentClass() );
  if ( !featureClass )
  {
    emit message( tr( "Define a feature class to measure (GeoStation ▸ Feature Classes…)." ), true );
    return false;
  }
  if ( mFeature.vertices.size() < featureClass->minimumVertices() )
  {
    emit message( tr( "A %1 needs %2 vertices; this one has %3." )
                  .arg( GeoStationFeatureClass::geometryName( featureClass->geometry ) ).arg( featureClass->minimumVertices() ).arg( mFeature.vertices.size() ), true );
    return false;
  }
  mFeature.className = featureClass->name;
  mFeature.measured = QDateTime::currentDateTimeUtc().toString( Qt::ISODateWithMs );
  mFeature.measurementId = QUuid::createUuid().toString( QUuid::WithoutBraces );
  const GeoStationMeasurementStore::Result result = mStore->addFeature( mFeature );
  emit message( tr( "%1 (%2 vertices, %3): %4" ).arg( featureClass->name ).arg( mFeature.vertices.size() ).arg( mFeature.method(), result.message ), !result.committed );
  if ( !result.ok )
    return false; // kept here: the operator can fix the problem and finish again
  mFeature = GeoStationMeasuredFeature();
  mOperatorVertices.clear();
  emit featureChanged();
  emit featureWritten( featureClass->layerName() );
  return true;
}

void GeoStationMeasurementController::cancel()
{
  resetViews();
  if ( !mFeature.vertices.isEmpty() )
    emit message( tr( "Feature with %1 vertices dropped." ).arg( mFeature.vertices.size() ), false );
  mFeature = GeoStationMeasuredFeature();
  mOperatorVertices.clear();
  emit viewStatesChanged();
  emit featureChanged();
}

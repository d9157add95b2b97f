/***************************************************************************
  overviewlayers.cpp
 ***************************************************************************/
#include "overviewlayers.h"

#include <map>

#include <qgscoordinatetransform.h>
#include <qgslayertree.h>
#include <qgslinestring.h>
#include <qgsmapcanvas.h>
#include <qgspolygon.h>
#include <qgsproject.h>
#include <qgsrasterdataprovider.h>
#include <qgsrasterlayer.h>
#include <qgsrubberband.h>
#include <qgsvectordataprovider.h>
#include <qgsvectorlayer.h>

#include "multiviewsession.h"
#include "workstation/viewcone.h"

namespace
{
  const QString sGroupName = QStringLiteral( "GeoStation overview" );
  const QString sProperty = QStringLiteral( "geostation/overview" );
}

GeoStationOverviewLayers::GeoStationOverviewLayers( GeoStationMultiviewSession *session, QgsProject *project, QgsMapCanvas *canvas, QObject *parent )
  : QObject( parent )
  , mSession( session )
  , mProject( project )
  , mCanvas( canvas )
{
  connect( mSession, &GeoStationMultiviewSession::blockChanged, this, &GeoStationOverviewLayers::rebuild );
  connect( mSession, &GeoStationMultiviewSession::blockReloaded, this, &GeoStationOverviewLayers::rebuild );
  connect( mSession, &GeoStationMultiviewSession::stationChanged, this, &GeoStationOverviewLayers::updateCurrentStation );
  connect( mSession, &GeoStationMultiviewSession::settingsChanged, this, &GeoStationOverviewLayers::updateCurrentStation );
}

GeoStationOverviewLayers::~GeoStationOverviewLayers()
{
  delete mHighlight;
  delete mTraced;
}

void GeoStationOverviewLayers::setTracedLine( const QVector<QgsPoint> &pointsInBlockCrs )
{
  if ( !mCanvas )
    return;
  if ( !mTraced )
  {
    mTraced = new QgsRubberBand( mCanvas, QgsWkbTypes::LineGeometry );
    mTraced->setStrokeColor( QColor( 0, 220, 255 ) );
    mTraced->setWidth( 3 );
  }
  mTracedVertices = pointsInBlockCrs.size() >= 2 ? pointsInBlockCrs.size() : 0;
  if ( mTracedVertices == 0 )
  {
    mTraced->reset( QgsWkbTypes::LineGeometry );
    return;
  }
  // the rubber band transforms from the block CRS to the canvas's
  mTraced->setToGeometry( QgsGeometry( new QgsLineString( pointsInBlockCrs ) ), mSession->crs() );
}

QgsVectorLayer *GeoStationOverviewLayers::addLayer( const QString &uri, const QString &name )
{
  QgsVectorLayer *layer = new QgsVectorLayer( uri, name, QStringLiteral( "memory" ) );
  layer->setCustomProperty( sProperty, true );
  // memory layers are rebuilt from the block; do not ask to save them
  layer->setCustomProperty( QStringLiteral( "skipMemoryLayersCheck" ), 1 );
  QgsLayerTreeGroup *group = mProject->layerTreeRoot()->findGroup( sGroupName );
  if ( !group )
    group = mProject->layerTreeRoot()->insertGroup( 0, sGroupName );
  mProject->addMapLayer( layer, false );
  group->addLayer( layer );
  return layer;
}

void GeoStationOverviewLayers::removeLayers()
{
  QStringList ids;
  for ( QgsMapLayer *layer : mProject->mapLayers() )
    if ( layer->customProperty( sProperty ).toBool() )
      ids << layer->id();
  mProject->removeMapLayers( ids );
  if ( QgsLayerTreeGroup *group = mProject->layerTreeRoot()->findGroup( sGroupName ) )
    if ( group->children().isEmpty() )
      mProject->layerTreeRoot()->removeChildNode( group );
  if ( mHighlight )
    mHighlight->reset( QgsWkbTypes::PointGeometry );
}

void GeoStationOverviewLayers::rebuild()
{
  removeLayers();
  const geostation::Block *block = mSession->block();
  if ( !block )
    return;
  const QgsCoordinateReferenceSystem &crs = mSession->crs();
  const QString crsPart = crs.isValid() ? QStringLiteral( "?crs=%1" ).arg( crs.authid().isEmpty() ? QStringLiteral( "wkt:" ) + crs.toWkt() : crs.authid() ) : QStringLiteral( "?" );
  const QString amp = crs.isValid() ? QStringLiteral( "&" ) : QString();

  mCones = addLayer( QStringLiteral( "PolygonZ%1%2field=image_id:string&field=camera:string&field=station:string" ).arg( crsPart, amp ), tr( "View cones" ) );
  mStations = addLayer( QStringLiteral( "PointZ%1%2field=station:string&field=time:string&field=trajectory:string&field=images:integer&field=run_index:integer" ).arg( crsPart, amp ), tr( "Stations" ) );
  mTrajectory = addLayer( QStringLiteral( "LineStringZ%1%2field=trajectory:string&field=stations:integer" ).arg( crsPart, amp ), tr( "Trajectory" ) );

  const geostation::StationSequence &run = mSession->run();
  QgsFeatureList stations;
  std::map<std::string, QgsPointSequence> lines;
  std::map<std::string, int> counts;
  for ( int i = 0; i < run.size(); ++i )
  {
    const geostation::SequenceStation &s = run.at( i );
    if ( !s.position )
      continue;
    const QgsPoint p( s.position->x(), s.position->y(), s.position->z() );
    QgsFeature f( mStations->fields() );
    f.setGeometry( QgsGeometry( p.clone() ) );
    f.setAttributes( QgsAttributes() << QString::fromStdString( s.id ) << QString::fromStdString( s.time ) << QString::fromStdString( s.trajectory ) << static_cast<int>( s.imageIds.size() ) << i );
    stations << f;
    lines[s.trajectory].append( p );
    ++counts[s.trajectory];
  }
  mStations->dataProvider()->addFeatures( stations );
  QgsFeatureList trajectories;
  for ( const auto &[name, points] : lines )
  {
    if ( points.size() < 2 )
      continue;
    QgsFeature f( mTrajectory->fields() );
    f.setGeometry( QgsGeometry( new QgsLineString( points ) ) );
    f.setAttributes( QgsAttributes() << QString::fromStdString( name ) << counts[name] );
    trajectories << f;
  }
  mTrajectory->dataProvider()->addFeatures( trajectories );
  for ( QgsVectorLayer *layer : { mCones.data(), mStations.data(), mTrajectory.data() } )
    layer->updateExtents();
  mCones->setOpacity( 0.4 ); // the map and the measurements stay visible under the cones
  if ( mCanvas && mStations->featureCount() > 0 )
  {
    // show the whole run when it is not on screen yet
    QgsCoordinateTransform toCanvas( mStations->crs(), mCanvas->mapSettings().destinationCrs(), mProject->transformContext() );
    try
    {
      QgsRectangle extent = toCanvas.transformBoundingBox( mStations->extent() );
      extent.grow( std::max( 20.0, 0.1 * std::max( extent.width(), extent.height() ) ) );
      if ( !mCanvas->extent().intersects( extent ) || mCanvas->extent().isEmpty() )
        mCanvas->setExtent( extent );
    }
    catch ( const QgsCsException & )
    {
    }
  }
  updateCurrentStation();
}

double GeoStationOverviewLayers::groundHeightUnder( double x, double y, double cameraZ ) const
{
  if ( QgsRasterLayer *dem = qobject_cast<QgsRasterLayer *>( mProject->mapLayer( mSession->demLayerId() ) ) )
  {
    try
    {
      const QgsCoordinateTransform toDem( mSession->crs(), dem->crs(), mProject->transformContext() );
      bool ok = false;
      const double z = dem->dataProvider()->sample( toDem.transform( QgsPointXY( x, y ) ), 1, &ok );
      if ( ok )
        return z;
    }
    catch ( const QgsCsException & )
    {
    }
  }
  return cameraZ - mSession->cameraHeightAboveRoadM();
}

void GeoStationOverviewLayers::updateCurrentStation()
{
  if ( !mCones || !mSession->block() )
    return;
  const int index = mSession->currentStation();
  mCones->dataProvider()->truncate();
  if ( index < 0 )
    return;
  const geostation::SequenceStation &station = mSession->run().at( index );
  QgsFeatureList cones;
  for ( const std::string &id : station.imageIds )
  {
    const geostation::OrientedImage *image = mSession->orientedImage( QString::fromStdString( id ) );
    if ( !image )
      continue;
    geostation::ViewConeOptions options;
    const Eigen::Vector3d c = image->exterior().projectionCentre;
    options.groundHeightM = groundHeightUnder( c.x(), c.y(), c.z() );
    options.maxRangeM = std::max( 40.0, 3.0 * ( c.z() - options.groundHeightM ) );
    const std::vector<Eigen::Vector2d> ring = geostation::viewCone( *image, options );
    if ( ring.size() < 3 )
      continue;
    QgsPointSequence points;
    for ( const Eigen::Vector2d &p : ring )
      points << QgsPoint( p.x(), p.y(), options.groundHeightM );
    points << points.first();
    QgsPolygon *polygon = new QgsPolygon();
    polygon->setExteriorRing( new QgsLineString( points ) );
    QgsFeature f( mCones->fields() );
    f.setGeometry( QgsGeometry( polygon ) );
    f.setAttributes( QgsAttributes() << QString::fromStdString( id ) << QString::fromStdString( mSession->block()->image( id ).cameraId ) << QString::fromStdString( station.id ) );
    cones << f;
  }
  mCones->dataProvider()->addFeatures( cones );
  mCones->updateExtents();
  mCones->triggerRepaint();

  if ( !mCanvas || !station.position )
    return;
  // highlight and keep in view
  const QgsCoordinateTransform toCanvas( mStations->crs(), mCanvas->mapSettings().destinationCrs(), mProject->transformContext() );
  QgsPointXY onCanvas;
  try
  {
    onCanvas = toCanvas.transform( QgsPointXY( station.position->x(), station.position->y() ) );
  }
  catch ( const QgsCsException & )
  {
    return;
  }
  if ( !mHighlight )
  {
    mHighlight = new QgsRubberBand( mCanvas, QgsWkbTypes::PointGeometry );
    mHighlight->setIcon( QgsRubberBand::ICON_CIRCLE );
    mHighlight->setIconSize( 18 );
    mHighlight->setWidth( 3 );
    mHighlight->setStrokeColor( QColor( 255, 0, 160 ) );
  }
  mHighlight->reset( QgsWkbTypes::PointGeometry );
  mHighlight->addPoint( onCanvas );
  QgsRectangle inner = mCanvas->extent();
  inner.scale( 0.8 );
  if ( !inner.contains( onCanvas ) )
    mCanvas->setCenter( onCanvas );
  mCanvas->refresh();
}

int GeoStationOverviewLayers::stationNearestToMapPoint( const QgsPointXY &pointInCanvasCrs ) const
{
  if ( !mStations || !mCanvas )
    return -1;
  try
  {
    const QgsCoordinateTransform toBlock( mCanvas->mapSettings().destinationCrs(), mStations->crs(), mProject->transformContext() );
    const QgsPointXY p = toBlock.transform( pointInCanvasCrs );
    return mSession->run().indexNearest( Eigen::Vector2d( p.x(), p.y() ) );
  }
  catch ( const QgsCsException & )
  {
    return -1;
  }
}


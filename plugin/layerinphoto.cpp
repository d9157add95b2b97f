/***************************************************************************
  layerinphoto.cpp - any map layer drawn in the photo, hidden parts marked
 ***************************************************************************/
#include "layerinphoto.h"

#include <algorithm>
#include <limits>

#include <qgscoordinatetransform.h>
#include <qgsfeatureiterator.h>
#include <qgsgeometry.h>
#include <qgslinestring.h>
#include <qgsmultilinestring.h>
#include <qgsmultipoint.h>
#include <qgsproject.h>
#include <qgsrasterlayer.h>
#include <qgsrubberband.h>

#include "dem/dem.h"
#include "dem/featureinphoto.h"
#include "geometry/imagespace.h"
#include "imageview.h"
#include "multiviewdock.h"
#include "multiviewsession.h"

GeoStationLayerInPhoto::GeoStationLayerInPhoto( GeoStationMultiviewSession *session, GeoStationMultiviewDock *multiview, QObject *parent )
  : QObject( parent )
  , mSession( session )
  , mMultiview( multiview )
{
  mTimer.setSingleShot( true );
  mTimer.setInterval( 150 );
  connect( &mTimer, &QTimer::timeout, this, &GeoStationLayerInPhoto::redraw );
  connect( mSession, &GeoStationMultiviewSession::viewImagesChanged, this, &GeoStationLayerInPhoto::scheduleRedraw );
  connect( mSession, &GeoStationMultiviewSession::settingsChanged, this, &GeoStationLayerInPhoto::scheduleRedraw );
}

GeoStationLayerInPhoto::~GeoStationLayerInPhoto()
{
  clear();
}

void GeoStationLayerInPhoto::setLayer( QgsVectorLayer *layer )
{
  if ( mLayer )
    disconnect( mLayer, nullptr, this, nullptr );
  mLayer = layer;
  if ( layer )
  {
    // edits, including those still in the edit buffer, and the layer's removal
    connect( layer, &QgsVectorLayer::featureAdded, this, &GeoStationLayerInPhoto::scheduleRedraw );
    connect( layer, &QgsVectorLayer::featureDeleted, this, &GeoStationLayerInPhoto::scheduleRedraw );
    connect( layer, &QgsVectorLayer::geometryChanged, this, &GeoStationLayerInPhoto::scheduleRedraw );
    connect( layer, &QgsVectorLayer::dataChanged, this, &GeoStationLayerInPhoto::scheduleRedraw );
  }
  redraw();
}

void GeoStationLayerInPhoto::setPhoto( const QString &imageId, const std::optional<geostation::OrientedImage> &image )
{
  mImageId = imageId;
  mImage = image;
  mMonoplotter.reset(); // it refers to the image
  scheduleRedraw();
}

void GeoStationLayerInPhoto::scheduleRedraw()
{
  mTimer.start();
}

void GeoStationLayerInPhoto::clear()
{
  for ( const Bands &b : std::as_const( mBands ) )
    if ( b.canvas )
    {
      delete b.visible;
      delete b.hidden;
      delete b.visiblePoints;
      delete b.hiddenPoints;
    }
  mBands.clear();
}

const geostation::Monoplotter *GeoStationLayerInPhoto::monoplotter()
{
  QgsRasterLayer *demLayer = qobject_cast<QgsRasterLayer *>( QgsProject::instance()->mapLayer( mSession->demLayerId() ) );
  if ( !demLayer || !mImage || !mSession->block() )
    return nullptr;
  try
  {
    if ( demLayer->source() != mDemPath || !mDem )
    {
      mMonoplotter.reset();
      mBlockToDem.reset();
      mDem.reset();
      mDemPath = demLayer->source();
      mDem = std::make_unique<geostation::Dem>( mDemPath.toStdString() );
      mBlockToDem = std::make_unique<geostation::CrsTransform>( mSession->block()->crs, mDem->crsWkt() );
    }
    if ( !mMonoplotter )
      mMonoplotter = std::make_unique<geostation::Monoplotter>( *mImage, *mDem, *mBlockToDem );
  }
  catch ( const std::exception & )
  {
    mDem.reset();
    return nullptr; // drawn without the terrain: nothing hidden
  }
  return mMonoplotter.get();
}

void GeoStationLayerInPhoto::redraw()
{
  clear();
  mVisibleParts = mHiddenParts = mSkipped = 0;
  if ( !mLayer || !mImage || !mMultiview || !mSession->block() )
    return;
  const geostation::Monoplotter *mono = monoplotter();
  const QgsCoordinateTransform toBlock( mLayer->crs(), mSession->crs(), QgsProject::instance() );
  QgsMultiLineString visible, hidden;
  QgsMultiPoint visiblePoints, hiddenPoints;
  QgsFeature feature;
  QgsFeatureIterator it = mLayer->getFeatures();
  while ( it.nextFeature( feature ) )
  {
    if ( !feature.hasGeometry() )
      continue;
    QgsGeometry geometry = feature.geometry();
    try
    {
      geometry.transform( toBlock );
    }
    catch ( const QgsCsException & )
    {
      ++mSkipped;
      continue;
    }
    // every vertex part (point, line, ring) as a list of map vertices (Z NaN where a vertex has none)
    QVector<std::vector<Eigen::Vector3d>> parts( 1 );
    QgsVertexId id, previous;
    QgsPoint p;
    const QgsAbstractGeometry *g = geometry.constGet();
    while ( g->nextVertex( id, p ) )
    {
      if ( !parts.last().empty() && ( id.part != previous.part || id.ring != previous.ring ) )
        parts.append( std::vector<Eigen::Vector3d>() );
      previous = id;
      parts.last().emplace_back( p.x(), p.y(), p.is3D() ? p.z() : std::numeric_limits<double>::quiet_NaN() );
    }
    // core's one rule for a map feature in a photo: heights from the feature's Z, else the DEM; a feature with a vertex
    // that has neither is skipped whole
    geostation::FeatureHeights heights;
    heights.dem = mono;
    QVector<geostation::GroundPart> ground;
    for ( const std::vector<Eigen::Vector3d> &part : std::as_const( parts ) )
      ground << geostation::groundPart( part, heights );
    if ( std::any_of( ground.cbegin(), ground.cend(), []( const geostation::GroundPart & part ) { return part.status != geostation::FeatureHeightStatus::Ok; } ) )
    {
      ++mSkipped;
      continue;
    }
    geostation::LineInPhotoOptions split;
    split.splitHidden = true; // rings too are drawn as lines, split where the terrain hides them
    for ( const geostation::GroundPart &part : std::as_const( ground ) )
    {
      if ( part.vertices.size() == 1 )
      {
        const geostation::GroundPointView seen = geostation::pointInPhoto( *mImage, part.vertices.front(), heights );
        if ( !seen.projection.ok() )
          continue;
        const bool isHidden = seen.projection.inFrame && !seen.visible;
        const Eigen::Vector2d xy = geostation::imageSpaceOfPixel( seen.projection.pixelInImage );
        ( isHidden ? hiddenPoints : visiblePoints ).addGeometry( new QgsPoint( xy.x(), xy.y() ) );
        ( isHidden ? mHiddenParts : mVisibleParts ) += 1;
        continue;
      }
      const geostation::ProjectedGroundLine runs = geostation::lineInPhoto( *mImage, part, heights, split );
      for ( size_t r = 0; r < runs.parts.size(); ++r )
      {
        QgsLineString *line = new QgsLineString();
        for ( const Eigen::Vector2d &px : runs.parts[r] )
        {
          const Eigen::Vector2d xy = geostation::imageSpaceOfPixel( px );
          line->addVertex( QgsPoint( xy.x(), xy.y() ) );
        }
        ( runs.hidden[r] ? hidden : visible ).addGeometry( line );
        ( runs.hidden[r] ? mHiddenParts : mVisibleParts ) += 1;
      }
    }
  }
  for ( int v = 0; v < mMultiview->viewCount(); ++v )
  {
    GeoStationImageView *view = mMultiview->view( v );
    if ( !view || view->imageId() != mImageId || !view->hasImage() )
      continue;
    Bands b;
    b.canvas = view->canvas();
    b.visible = new QgsRubberBand( view->canvas(), QgsWkbTypes::LineGeometry );
    b.visible->setStrokeColor( QColor( 0, 230, 255, 230 ) );
    b.visible->setWidth( 2 );
    b.visible->setToGeometry( view->inView( QgsGeometry( visible.clone() ) ) );
    b.hidden = new QgsRubberBand( view->canvas(), QgsWkbTypes::LineGeometry );
    b.hidden->setStrokeColor( QColor( 255, 40, 40, 200 ) );
    b.hidden->setLineStyle( Qt::DashLine );
    b.hidden->setWidth( 2 );
    b.hidden->setToGeometry( view->inView( QgsGeometry( hidden.clone() ) ) );
    b.visiblePoints = new QgsRubberBand( view->canvas(), QgsWkbTypes::PointGeometry );
    b.visiblePoints->setColor( QColor( 0, 230, 255 ) );
    b.visiblePoints->setIcon( QgsRubberBand::ICON_CIRCLE );
    b.visiblePoints->setToGeometry( view->inView( QgsGeometry( visiblePoints.clone() ) ) );
    b.hiddenPoints = new QgsRubberBand( view->canvas(), QgsWkbTypes::PointGeometry );
    b.hiddenPoints->setColor( QColor( 255, 40, 40 ) );
    b.hiddenPoints->setIcon( QgsRubberBand::ICON_X );
    b.hiddenPoints->setToGeometry( view->inView( QgsGeometry( hiddenPoints.clone() ) ) );
    mBands << b;
  }
}

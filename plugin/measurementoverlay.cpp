/***************************************************************************
  measurementoverlay.cpp
 ***************************************************************************/
#include "measurementoverlay.h"

#include <algorithm>
#include <limits>

#include <qgscoordinatetransform.h>
#include <qgsfeatureiterator.h>
#include <qgsfeaturerequest.h>
#include <qgslinestring.h>
#include <qgsmultilinestring.h>
#include <qgsproject.h>
#include <qgsvectorlayer.h>

#include "dem/featureinphoto.h"
#include "geometry/imagespace.h"

namespace
{
  QgsPointXY toView( const Eigen::Vector2d &pixel )
  {
    const Eigen::Vector2d xy = geostation::imageSpaceOfPixel( pixel );
    return QgsPointXY( xy.x(), xy.y() );
  }

  /**
   * The heights of the overlay: a measured feature's own Z; a vertex without
   * one (a 2-D layer) lies on the plane Z = 0 (the Multiview has no DEM of
   * its own).
   */
  geostation::FeatureHeights overlayHeights()
  {
    geostation::FeatureHeights heights;
    heights.planeZ = 0.0;
    return heights;
  }

  //! A polyline or ring (block CRS) in the image by core's rule, its parts that reach into the frame added to `out`.
  void addPolyline( const geostation::OrientedImage &image, const std::vector<Eigen::Vector3d> &vertices, bool closed, double densifyPx, QgsMultiLineString &out )
  {
    if ( vertices.size() < 2 )
      return;
    const geostation::FeatureHeights heights = overlayHeights();
    geostation::LineInPhotoOptions options;
    options.densifyPx = densifyPx;
    options.closed = closed;
    for ( const std::vector<Eigen::Vector2d> &part : geostation::lineInPhoto( image, geostation::groundPart( vertices, heights ), heights, options ).parts )
    {
      if ( std::none_of( part.begin(), part.end(), [&image]( const Eigen::Vector2d & px ) { return image.camera().isInFrame( px ); } ) )
        continue;
      QVector<QgsPointXY> line;
      for ( const Eigen::Vector2d &px : part )
        line << toView( px );
      out.addGeometry( QgsLineString( line ).clone() );
    }
  }
}

QVector<QgsGeometry> projectFeaturesIntoImage( const QList<QgsVectorLayer *> &layers, const geostation::OrientedImage &image,
    const QgsCoordinateReferenceSystem &blockCrs, const GeoStationOverlayOptions &options )
{
  QVector<QgsGeometry> out;
  const Eigen::Vector3d centre = image.exterior().projectionCentre;
  for ( QgsVectorLayer *layer : layers )
  {
    if ( !layer || !layer->isValid() || !layer->isSpatial() )
      continue;
    const QgsCoordinateTransform toBlock( layer->crs(), blockCrs, QgsProject::instance()->transformContext() );
    QgsRectangle near( centre.x() - options.maxRangeM, centre.y() - options.maxRangeM, centre.x() + options.maxRangeM, centre.y() + options.maxRangeM );
    QgsFeatureRequest request;
    request.setNoAttributes();
    try
    {
      if ( toBlock.isValid() && !toBlock.isShortCircuited() )
        near = toBlock.transformBoundingBox( near, Qgis::TransformDirection::Reverse );
    }
    catch ( const QgsCsException & )
    {
      continue;
    }
    request.setFilterRect( near );
    QgsFeatureIterator it = layer->getFeatures( request );
    QgsFeature f;
    while ( it.nextFeature( f ) )
    {
      QgsGeometry g = f.geometry();
      if ( g.isNull() )
        continue;
      try
      {
        if ( toBlock.isValid() && !toBlock.isShortCircuited() )
          g.transform( toBlock );
      }
      catch ( const QgsCsException & )
      {
        continue;
      }
      if ( g.type() == QgsWkbTypes::PointGeometry )
      {
        const geostation::FeatureHeights heights = overlayHeights();
        for ( auto v = g.vertices_begin(); v != g.vertices_end(); ++v )
        {
          const Eigen::Vector3d ground = geostation::groundPart( { Eigen::Vector3d( ( *v ).x(), ( *v ).y(), ( *v ).z() ) }, heights ).vertices.front();
          const geostation::GroundProjection p = geostation::pointInPhoto( image, ground, heights ).projection;
          if ( p.ok() && p.inFrame )
            out << QgsGeometry::fromPointXY( toView( p.pixelInImage ) );
        }
        continue;
      }
      // lines and polygon rings (clipped as rings, drawn as lines), part by part
      QgsMultiLineString lines;
      const bool rings = g.type() == QgsWkbTypes::PolygonGeometry;
      const QgsGeometry boundary = rings ? QgsGeometry( g.constGet()->boundary() ) : g;
      for ( auto part = boundary.const_parts_begin(); part != boundary.const_parts_end(); ++part )
      {
        const QgsLineString *line = qgsgeometry_cast<const QgsLineString *>( *part );
        if ( !line )
          continue;
        std::vector<Eigen::Vector3d> vertices;
        for ( int i = 0; i < line->numPoints(); ++i )
          vertices.emplace_back( line->xAt( i ), line->yAt( i ), line->is3D() ? line->zAt( i ) : std::numeric_limits<double>::quiet_NaN() );
        addPolyline( image, vertices, rings, options.densifyPx, lines );
      }
      if ( lines.numGeometries() > 0 )
        out << QgsGeometry( lines.clone() );
    }
  }
  return out;
}

QgsGeometry projectPolylineIntoImage( const std::vector<Eigen::Vector3d> &vertices, const geostation::OrientedImage &image, const GeoStationOverlayOptions &options )
{
  // the parts within range of the camera
  QgsMultiLineString pieces;
  const Eigen::Vector3d centre = image.exterior().projectionCentre;
  std::vector<Eigen::Vector3d> run;
  for ( size_t i = 0; i <= vertices.size(); ++i )
  {
    if ( i < vertices.size() && ( vertices[i] - centre ).head<2>().norm() <= options.maxRangeM )
    {
      run.push_back( vertices[i] );
      continue;
    }
    addPolyline( image, run, false, options.densifyPx, pieces );
    run.clear();
  }
  if ( pieces.numGeometries() == 0 )
    return QgsGeometry();
  return QgsGeometry( pieces.clone() );
}

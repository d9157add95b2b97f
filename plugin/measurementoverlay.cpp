/***************************************************************************
  measurementoverlay.cpp
 ***************************************************************************/
#include "measurementoverlay.h"

#include <qgscoordinatetransform.h>
#include <qgsfeatureiterator.h>
#include <qgsfeaturerequest.h>
#include <qgslinestring.h>
#include <qgsmultilinestring.h>
#include <qgsproject.h>
#include <qgsvectorlayer.h>

namespace
{
  QgsPointXY toView( const Eigen::Vector2d &pixel )
  {
    return QgsPointXY( pixel.x(), -pixel.y() );
  }

  //! Projected pieces of a 3D polyline (pieces broken where a point cannot be projected).
  void addPolyline( const geostation::OrientedImage &image, const std::vector<Eigen::Vector3d> &vertices, double densifyPx, QgsMultiLineString &out )
  {
    if ( vertices.size() < 2 )
      return;
    const std::vector<Eigen::Vector3d> dense = geostation::densifyForImage( image, vertices, densifyPx );
    QVector<QgsPointXY> piece;
    bool anyInFrame = false;
    const auto flush = [&]
    {
      if ( piece.size() >= 2 && anyInFrame )
        out.addGeometry( QgsLineString( piece ).clone() );
      piece.clear();
      anyInFrame = false;
    };
    for ( const Eigen::Vector3d &p : dense )
    {
      const geostation::GroundProjection g = image.projectGroundToPixel( p );
      if ( !g.ok() )
      {
        flush();
        continue;
      }
      piece << toView( g.pixelInImage );
      anyInFrame = anyInFrame || g.inFrame;
    }
    flush();
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
        for ( auto v = g.vertices_begin(); v != g.vertices_end(); ++v )
        {
          const geostation::GroundProjection p = image.projectGroundToPixel( Eigen::Vector3d( ( *v ).x(), ( *v ).y(), ( *v ).is3D() ? ( *v ).z() : 0.0 ) );
          if ( p.ok() && p.inFrame )
            out << QgsGeometry::fromPointXY( toView( p.pixelInImage ) );
        }
        continue;
      }
      // lines and polygon rings, part by part
      QgsMultiLineString lines;
      const QgsGeometry boundary = g.type() == QgsWkbTypes::PolygonGeometry ? QgsGeometry( g.constGet()->boundary() ) : g;
      for ( auto part = boundary.const_parts_begin(); part != boundary.const_parts_end(); ++part )
      {
        const QgsLineString *line = qgsgeometry_cast<const QgsLineString *>( *part );
        if ( !line )
          continue;
        std::vector<Eigen::Vector3d> vertices;
        for ( int i = 0; i < line->numPoints(); ++i )
          vertices.emplace_back( line->xAt( i ), line->yAt( i ), line->is3D() ? line->zAt( i ) : 0.0 );
        addPolyline( image, vertices, options.densifyPx, lines );
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
    addPolyline( image, run, options.densifyPx, pieces );
    run.clear();
  }
  if ( pieces.numGeometries() == 0 )
    return QgsGeometry();
  return QgsGeometry( pieces.clone() );
}

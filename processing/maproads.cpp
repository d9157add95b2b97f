/***************************************************************************
  maproads.cpp - a road map layer read for core/revision
 ***************************************************************************/
#include "maproads.h"

#include <cmath>

#include <qgscoordinatetransform.h>
#include <qgsexception.h>
#include <qgsfeatureiterator.h>
#include <qgsfeaturesource.h>
#include <qgslinestring.h>
#include <qgsprocessingfeedback.h>

namespace GeoStationProcessing
{

namespace
{
  //! The geometry in the block CRS, or a null geometry where it has none or cannot be carried there.
  QgsGeometry inBlockCrs( const QgsFeature &f, const QgsCoordinateTransform &toBlock )
  {
    QgsGeometry g = f.geometry();
    if ( g.isNull() || g.isEmpty() )
      return QgsGeometry();
    try
    {
      g.transform( toBlock );
    }
    catch ( const QgsCsException & )
    {
      return QgsGeometry();
    }
    return g;
  }
}

MapRoads readMapRoads( QgsFeatureSource &map, const QgsCoordinateTransform &toBlock, QgsProcessingFeedback *feedback )
{
  MapRoads lines;
  QgsFeature f;
  QgsFeatureIterator it = map.getFeatures();
  while ( it.nextFeature( f ) )
  {
    if ( feedback && feedback->isCanceled() )
      break;
    const QgsGeometry g = inBlockCrs( f, toBlock );
    const size_t before = lines.roads.size();
    const bool hasZ = !g.isNull() && QgsWkbTypes::hasZ( g.wkbType() );
    int partIndex = 0;
    if ( !g.isNull() )
      for ( auto part = g.const_parts_begin(); part != g.const_parts_end(); ++part, ++partIndex )
      {
        geostation::MapRoad road;
        for ( auto v = ( *part )->vertices_begin(); v != ( *part )->vertices_end(); ++v )
          road.vertices.emplace_back( ( *v ).x(), ( *v ).y(), hasZ && std::isfinite( ( *v ).z() ) ? ( *v ).z() : std::nan( "" ) );
        if ( !road.vertices.empty() )
        {
          lines.roads.push_back( road );
          lines.source.push_back( f );
          lines.part.push_back( partIndex );
        }
      }
    if ( lines.roads.size() == before )
    {
      lines.roads.emplace_back(); // no geometry: invalid_geometry, its row kept
      lines.source.push_back( f );
      lines.part.push_back( 0 );
    }
  }
  return lines;
}

QgsGeometry lineStringZ( const std::vector<Eigen::Vector3d> &points )
{
  QVector<double> x, y, z;
  for ( const Eigen::Vector3d &p : points )
  {
    x << p.x();
    y << p.y();
    z << ( std::isfinite( p.z() ) ? p.z() : 0.0 );
  }
  return QgsGeometry( new QgsLineString( x, y, z ) );
}

} // namespace GeoStationProcessing

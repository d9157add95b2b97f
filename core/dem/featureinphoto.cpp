/***************************************************************************
  featureinphoto.cpp
 ***************************************************************************/
#include "dem/featureinphoto.h"

#include <cmath>
#include <stdexcept>

namespace geostation
{

  GroundPart groundPart( const std::vector<Eigen::Vector3d> &vertices, const FeatureHeights &heights )
  {
    GroundPart part;
    part.draped = !vertices.empty();
    part.vertices.reserve( vertices.size() );
    for ( size_t i = 0; i < vertices.size(); ++i )
    {
      const Eigen::Vector3d &v = vertices[i];
      if ( heights.featureZ && std::isfinite( v.z() ) )
      {
        part.vertices.emplace_back( v );
        part.draped = false;
        continue;
      }
      std::optional<double> z;
      if ( heights.dem )
        z = heights.dem->demHeightAt( Eigen::Vector3d( v.x(), v.y(), 0.0 ) );
      if ( !z )
      {
        part.draped = false;
        z = heights.planeZ;
      }
      if ( !z )
      {
        part.status = heights.dem ? FeatureHeightStatus::OutsideDem : FeatureHeightStatus::NoHeight;
        part.failedVertex = i;
        part.vertices.clear();
        part.draped = false;
        return part;
      }
      part.vertices.emplace_back( v.x(), v.y(), *z );
    }
    return part;
  }

  GroundPointView pointInPhoto( const OrientedImage &image, const Eigen::Vector3d &ground, const FeatureHeights &heights )
  {
    return featureViewer( image, heights.dem )( ground );
  }

  ProjectedGroundLine lineInPhoto( const OrientedImage &image, const GroundPart &part, const FeatureHeights &heights, const LineInPhotoOptions &options )
  {
    if ( part.status != FeatureHeightStatus::Ok )
      throw std::invalid_argument( "lineInPhoto: the part has no heights (its status is not Ok)" );
    GroundLineOptions line;
    line.densifyPx = options.densifyPx;
    line.closed = options.closed;
    line.splitHidden = options.splitHidden;
    if ( part.draped && heights.dem )
    {
      const Monoplotter *dem = heights.dem;
      line.heightAt = [dem]( const Eigen::Vector3d &p ) { return dem->demHeightAt( p ); };
    }
    return projectGroundLine( image, part.vertices, featureViewer( image, heights.dem ), line );
  }

} // namespace geostation

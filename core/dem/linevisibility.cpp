/***************************************************************************
  linevisibility.cpp - a map line in a photo, its hidden parts marked
 ***************************************************************************/
#include "dem/linevisibility.h"

#include <stdexcept>

namespace geostation
{

  std::vector<LineVisibilityRun> lineVisibilityRuns( const OrientedImage &image, const Monoplotter *monoplotter, const std::vector<Eigen::Vector3d> &vertices,
      double densifyPx )
  {
    if ( !( densifyPx > 0.0 ) )
      throw std::invalid_argument( "The densification step must be positive." );
    std::function<std::optional<double>( const Eigen::Vector3d & )> heightAt;
    if ( monoplotter )
      heightAt = [monoplotter]( const Eigen::Vector3d &p ) { return monoplotter->demHeightAt( p ); };
    const std::vector<Eigen::Vector3d> dense = densifyForImage( image, vertices, densifyPx, heightAt );
    const GroundPointViewer view = featureViewer( image, monoplotter );

    std::vector<LineVisibilityRun> runs;
    LineVisibilityRun current;
    auto close = [&]() {
      if ( current.pixels.size() >= 2 )
        runs.push_back( current );
      current = LineVisibilityRun();
    };
    for ( const Eigen::Vector3d &ground : dense )
    {
      const GroundPointView seen = view( ground );
      if ( !seen.projection.ok() )
      {
        close(); // behind the camera or outside the lens field: nothing to draw through
        continue;
      }
      const bool hidden = seen.projection.inFrame && !seen.visible;
      if ( !current.pixels.empty() && hidden != current.hidden )
      {
        // the boundary point belongs to both runs
        const Eigen::Vector2d last = current.pixels.back();
        close();
        current.pixels.push_back( last );
      }
      current.hidden = hidden;
      current.pixels.push_back( seen.projection.pixelInImage );
    }
    close();
    return runs;
  }

} // namespace geostation

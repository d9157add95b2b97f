/***************************************************************************
  viewcone.cpp
 ***************************************************************************/
#include "workstation/viewcone.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace geostation
{

  std::vector<Eigen::Vector2d> convexHull( std::vector<Eigen::Vector2d> points )
  {
    std::sort( points.begin(), points.end(), []( const Eigen::Vector2d &a, const Eigen::Vector2d &b )
    {
      return a.x() < b.x() || ( a.x() == b.x() && a.y() < b.y() );
    } );
    points.erase( std::unique( points.begin(), points.end() ), points.end() );
    if ( points.size() < 3 )
      return points;
    const auto cross = []( const Eigen::Vector2d &o, const Eigen::Vector2d &a, const Eigen::Vector2d &b )
    {
      return ( a.x() - o.x() ) * ( b.y() - o.y() ) - ( a.y() - o.y() ) * ( b.x() - o.x() );
    };
    std::vector<Eigen::Vector2d> hull( 2 * points.size() );
    size_t k = 0;
    for ( size_t i = 0; i < points.size(); ++i )
    {
      while ( k >= 2 && cross( hull[k - 2], hull[k - 1], points[i] ) <= 0 )
        --k;
      hull[k++] = points[i];
    }
    for ( size_t i = points.size() - 1, t = k + 1; i > 0; --i )
    {
      while ( k >= t && cross( hull[k - 2], hull[k - 1], points[i - 1] ) <= 0 )
        --k;
      hull[k++] = points[i - 1];
    }
    hull.resize( k - 1 );
    return hull;
  }

  std::vector<Eigen::Vector2d> viewCone( const OrientedImage &image, const ViewConeOptions &options )
  {
    if ( !( options.maxRangeM > 0 ) || options.samplesPerSide < 1 )
      throw std::invalid_argument( "viewCone: the range must be positive and at least one sample per side is needed" );
    const double w = image.camera().width, h = image.camera().height;
    std::vector<Eigen::Vector2d> border;
    const int n = options.samplesPerSide;
    for ( int i = 0; i <= n; ++i )
    {
      const double t = static_cast<double>( i ) / n;
      border.emplace_back( t * w, 0.0 );
      border.emplace_back( t * w, h );
      border.emplace_back( 0.0, t * h );
      border.emplace_back( w, t * h );
    }
    const Eigen::Vector3d centre = image.exterior().projectionCentre;
    std::vector<Eigen::Vector2d> points { centre.head<2>() };
    for ( const Eigen::Vector2d &pixel : border )
    {
      const std::optional<Ray> ray = image.worldRayFromPixel( pixel );
      if ( !ray )
        continue;
      const double horizontal = ray->direction.head<2>().norm();
      // the ray's parameter at the horizontal range (or "never" for a vertical ray)
      double t = horizontal > 1e-12 ? options.maxRangeM / horizontal : std::numeric_limits<double>::infinity();
      if ( ray->direction.z() < -1e-12 )
        t = std::min( t, ( options.groundHeightM - centre.z() ) / ray->direction.z() );
      if ( !std::isfinite( t ) || t < 0 )
        continue;
      points.push_back( ( centre + t * ray->direction ).head<2>() );
    }
    if ( points.size() < 3 )
      return {};
    return convexHull( points );
  }

} // namespace geostation

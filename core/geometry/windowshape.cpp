/***************************************************************************
  windowshape.cpp
 ***************************************************************************/
#include "geometry/windowshape.h"

#include <cmath>
#include <stdexcept>

#include <Eigen/LU>

namespace geostation
{

  std::optional<Eigen::Vector3d> roadPlanePoint( const OrientedImage &image, const Eigen::Vector2d &pixelInImage, double heightM )
  {
    const std::optional<Ray> ray = image.worldRayFromPixel( pixelInImage );
    if ( !ray || ray->direction.z() > -1e-3 )
      return std::nullopt;
    const double t = ( heightM - ray->origin.z() ) / ray->direction.z();
    if ( t <= 0 )
      return std::nullopt;
    return Eigen::Vector3d( ray->origin + t * ray->direction );
  }

  std::optional<PredictedWindow> predictWindowShape( const OrientedImage &reference, const Eigen::Vector2d &pixelInReference, const OrientedImage &search,
      const GroundOfPixel &groundOfPixel, double stepPx )
  {
    if ( !( stepPx > 0 ) )
      throw std::invalid_argument( "predictWindowShape: the difference step must be positive" );
    if ( !groundOfPixel )
      return std::nullopt;
    // the pixel's ground point and its projection into the search image
    const auto searchPixelOf = [&]( const Eigen::Vector2d &pixel ) -> std::optional<std::pair<Eigen::Vector3d, Eigen::Vector2d>>
    {
      const std::optional<Eigen::Vector3d> ground = groundOfPixel( reference, pixel );
      if ( !ground )
        return std::nullopt;
      const GroundProjection p = search.projectGroundToPixel( *ground );
      if ( !p.ok() )
        return std::nullopt;
      return std::make_pair( *ground, p.pixelInImage );
    };
    const auto centre = searchPixelOf( pixelInReference );
    if ( !centre )
      return std::nullopt;
    PredictedWindow out;
    out.groundPoint = centre->first;
    out.pixelInSearch = centre->second;
    for ( int k = 0; k < 2; ++k )
    {
      const Eigen::Vector2d step = stepPx * Eigen::Vector2d::Unit( k );
      const auto ahead = searchPixelOf( pixelInReference + step ), behind = searchPixelOf( pixelInReference - step );
      if ( !ahead || !behind )
        return std::nullopt;
      out.searchFromReference.col( k ) = ( ahead->second - behind->second ) / ( 2.0 * stepPx );
    }
    // a surface seen (nearly) edge-on in either image maps an area onto a line
    const double det = out.searchFromReference.determinant();
    if ( !std::isfinite( det ) || std::abs( det ) < 1e-6 )
      return std::nullopt;
    return out;
  }

} // namespace geostation

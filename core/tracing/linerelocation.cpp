/***************************************************************************
  linerelocation.cpp - a traced point put back onto the line, averaged along it
 ***************************************************************************/
#include "tracing/linerelocation.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace geostation
{

  void LineRelocation::check() const
  {
    if ( !( searchHalfPx > 0 ) || searchHalfPx > 20 )
      throw std::invalid_argument( "the search distance across the line must be between 0 and 20 px" );
    if ( !( windowM >= 0 ) || windowM > 10 )
      throw std::invalid_argument( "the length of line averaged must be between 0 and 10 m" );
    if ( maxAlongSamples < 1 )
      throw std::invalid_argument( "at least one profile must be averaged" );
  }

  std::optional<LineHit> relocateOnLine( const StereoImage &image, const Eigen::Vector2d &pixelInImage, const Eigen::Vector2d &direction, double pxPerM,
                                         double rangeM, const LineRelocation &relocation )
  {
    if ( !image.grey || !( direction.norm() > 0.5 ) || !std::isfinite( pxPerM ) || !( pxPerM > 0 ) )
      return std::nullopt;
    LineProfile profile = relocation.profile;
    if ( profile.kind != LineKind::Edge && relocation.widthTimesRange > 0 )
      profile.widthPx = relocation.widthTimesRange / std::max( rangeM, 1.0 );
    LocateOptions locate = locateOptionsFor( profile, FollowOptions(), relocation.searchHalfPx );
    const int window = static_cast<int>( std::lround( relocation.windowM * pxPerM ) );
    locate.alongSamples = std::clamp( window | 1, std::min( locate.alongSamples, relocation.maxAlongSamples ), relocation.maxAlongSamples );
    return locateLine( *image.grey, pixelInImage, direction, profile, locate );
  }

  int recentreOnLine( const StereoImage &image, std::vector<Eigen::Vector2d> &points, std::vector<double> &sigmasPx, const GroundOfPixel &groundOfPixel,
                      const LineRelocation &relocation )
  {
    relocation.check();
    if ( points.size() < 2 || !image.grey || !image.image || sigmasPx.size() != points.size() )
      return 0;
    const Eigen::Vector3d camera = image.image->exterior().projectionCentre;
    const std::vector<Eigen::Vector2d> followed = points;
    std::vector<std::optional<Eigen::Vector3d>> ground( followed.size() );
    for ( size_t i = 0; i < followed.size(); ++i )
      ground[i] = groundOfPixel( *image.image, followed[i] );
    int moved = 0;
    for ( size_t i = 0; i < followed.size(); ++i )
    {
      const size_t before = i == 0 ? 0 : i - 1, after = std::min( i + 1, followed.size() - 1 );
      const Eigen::Vector2d along = followed[after] - followed[before];
      if ( !ground[i] || !ground[before] || !ground[after] || along.norm() < 1e-6 )
        continue;
      const double metres = ( *ground[after] - *ground[before] ).norm();
      if ( !( metres > 1e-3 ) )
        continue;
      const std::optional<LineHit> hit = relocateOnLine( image, followed[i], along.normalized(), along.norm() / metres, ( *ground[i] - camera ).head<2>().norm(), relocation );
      if ( !hit )
        continue;
      points[i] = hit->pixelInImage;
      sigmasPx[i] = hit->sigmaPx;
      ++moved;
    }
    return moved;
  }

} // namespace geostation

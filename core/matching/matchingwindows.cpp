/***************************************************************************
  matchingwindows.cpp - the pixels a match reads
 ***************************************************************************/
#include "matching/matchingwindows.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace geostation
{
  namespace
  {
    //! Pixels around a position that matching reads: the largest window, stretched as far as the predicted shape may, and least squares' movement.
    int reachPx( const AreaMatchOptions &area )
    {
      const int side = std::max( { area.windowWidth, area.windowHeight, area.lsmOptions.windowWidth, area.lsmOptions.windowHeight } );
      return static_cast<int>( std::ceil( std::max( 1.0, area.maxAffineScale ) * side ) ) + 8;
    }

    cv::Rect around( const Eigen::Vector2d &lo, const Eigen::Vector2d &hi, int reach, const cv::Size &size )
    {
      const int x0 = static_cast<int>( std::floor( lo.x() ) ) - reach, y0 = static_cast<int>( std::floor( lo.y() ) ) - reach;
      const int x1 = static_cast<int>( std::ceil( hi.x() ) ) + reach, y1 = static_cast<int>( std::ceil( hi.y() ) ) + reach;
      return cv::Rect( x0, y0, x1 - x0, y1 - y0 ) & cv::Rect( 0, 0, size.width, size.height );
    }

    long long area( const cv::Rect &r ) { return static_cast<long long>( r.width ) * r.height; }

    /**
     * The window around the curve's vertices [first, last]; grown vertex by
     * vertex from `centre` while it stays within maxPixels.
     */
    cv::Rect windowAlong( const std::vector<Eigen::Vector2d> &curve, size_t centre, int reach, const cv::Size &size, long long maxPixels, bool &cut )
    {
      Eigen::Vector2d lo = curve[centre], hi = curve[centre];
      cv::Rect window = around( lo, hi, reach, size );
      size_t first = centre, last = centre;
      cut = false;
      while ( first > 0 || last + 1 < curve.size() )
      {
        bool grown = false;
        for ( const bool down : { true, false } )
        {
          if ( down ? first == 0 : last + 1 == curve.size() )
            continue;
          const Eigen::Vector2d &p = curve[down ? first - 1 : last + 1];
          const Eigen::Vector2d newLo = lo.cwiseMin( p ), newHi = hi.cwiseMax( p );
          const cv::Rect grownWindow = around( newLo, newHi, reach, size );
          if ( area( grownWindow ) > maxPixels )
            continue;
          lo = newLo;
          hi = newHi;
          window = grownWindow;
          if ( down )
            --first;
          else
            ++last;
          grown = true;
        }
        if ( !grown )
        {
          cut = true;
          break;
        }
      }
      return window;
    }
  }

  cv::Rect matchingWindowAround( const Eigen::Vector2d &pixelInImage, double radiusPx, const AreaMatchOptions &area, const cv::Size &imageSize )
  {
    return around( pixelInImage, pixelInImage, reachPx( area ) + static_cast<int>( std::ceil( std::max( 0.0, radiusPx ) ) ), imageSize );
  }

  cv::Rect matchingWindowAlong( const std::vector<Eigen::Vector2d> &curve, const AreaMatchOptions &area, const cv::Size &imageSize, long long maxPixels,
                                const std::optional<Eigen::Vector2d> &centre, bool *cut )
  {
    if ( cut )
      *cut = false;
    const cv::Rect image( 0, 0, imageSize.width, imageSize.height );
    std::vector<Eigen::Vector2d> inImage;
    for ( const Eigen::Vector2d &p : curve )
      if ( p.allFinite() && image.contains( cv::Point( static_cast<int>( std::floor( p.x() ) ), static_cast<int>( std::floor( p.y() ) ) ) ) )
        inImage.push_back( p );
    if ( inImage.empty() )
      return cv::Rect();
    size_t middle = inImage.size() / 2;
    if ( centre )
    {
      double nearest = std::numeric_limits<double>::infinity();
      for ( size_t k = 0; k < inImage.size(); ++k )
        if ( const double d = ( inImage[k] - *centre ).squaredNorm(); d < nearest )
        {
          nearest = d;
          middle = k;
        }
    }
    bool wasCut = false;
    const cv::Rect window = windowAlong( inImage, middle, reachPx( area ) + std::max( 0, area.bandHalfWidthPx ), imageSize, maxPixels, wasCut );
    if ( cut )
      *cut = wasCut;
    return window;
  }

} // namespace geostation

/***************************************************************************
  pointmatcher.cpp - a point measured in one image found in another image
 ***************************************************************************/
#include "workstation/pointmatcher.h"

#include <algorithm>
#include <stdexcept>

#include "matching/matchingwindows.h"

namespace geostation
{

  void PointMatchOptions::check() const
  {
    area.check();
    if ( !( epipolar.minDistanceM > 0.0 ) || !( epipolar.maxDistanceM > epipolar.minDistanceM ) )
      throw std::invalid_argument( "the epipolar search's farthest depth must be larger than its nearest, and both positive" );
    if ( !( searchRadiusPx > 0.0 ) )
      throw std::invalid_argument( "the search radius must be positive" );
  }

  PointMatcher::PointMatcher( const Block &block, const PointMatchOptions &options, MatchImageCache &cache )
    : mBlock( block )
    , mOptions( options )
    , mCache( cache )
  {
    options.check();
  }

  std::shared_ptr<const MatchImage> PointMatcher::imageFor( const BlockImage &image, const std::function<cv::Rect( const cv::Size & )> &window ) const
  {
    const std::string path = mBlock.imageFilePath( image ).string();
    MatchImageCache::Entry entry = mCache.get( path );
    if ( entry.needsWindow )
      if ( const cv::Rect pixels = window( entry.imageSize ); !pixels.empty() )
        entry = mCache.get( path, pixels );
    if ( !entry.ok() )
      mUnreadable[image.id] = entry.message;
    return entry.image;
  }

  AreaMatch PointMatcher::match( const BlockImage &reference, const Eigen::Vector2d &pixelInReference, const BlockImage &target,
                                 const std::optional<Eigen::Vector2d> &approximateInTarget ) const
  {
    const AreaMatchOptions &area = mOptions.area;
    const bool oriented = reference.exterior && target.exterior;
    std::vector<Eigen::Vector2d> curve;
    if ( oriented )
      for ( const auto &piece : epipolarCurve( mBlock.orientedImage( reference ), pixelInReference, mBlock.orientedImage( target ), mOptions.epipolar ).pieces )
        for ( const EpipolarVertex &v : piece )
          curve.push_back( v.pixelInImage );
    const std::shared_ptr<const MatchImage> from = imageFor( reference, [&]( const cv::Size &size ) { return matchingWindowAround( pixelInReference, 0.0, area, size ); } );
    const std::shared_ptr<const MatchImage> to = imageFor( target, [&]( const cv::Size &size ) {
      return oriented ? matchingWindowAlong( curve, area, size, mCache.maxWholePixels() )
             : approximateInTarget ? matchingWindowAround( *approximateInTarget, mOptions.searchRadiusPx, area, size ) : cv::Rect();
    } );
    AreaMatch m;
    m.status = MatchStatus::Outside;
    const std::string unreadable = mUnreadable.count( reference.id ) ? reference.id : mUnreadable.count( target.id ) ? target.id : std::string();
    if ( ( !from || !to ) && !unreadable.empty() )
      m.message = "the image " + unreadable + " cannot be read: " + mUnreadable.at( unreadable );
    else if ( !from )
      m.message = "the point lies outside its image";
    else if ( oriented && !to )
      m.message = "the epipolar curve does not cross the image";
    else if ( !oriented && !approximateInTarget )
      m.message = "the images are not both oriented and the point has no approximate position in the target";
    else if ( !to )
      m.message = "the approximate position lies outside the image";
    else if ( oriented )
    {
      AreaMatchOptions pointOptions = area;
      if ( mOptions.terrain )
        if ( const std::optional<PredictedWindow> w = predictWindowShape( mBlock.orientedImage( reference ), pixelInReference, mBlock.orientedImage( target ), mOptions.terrain,
                                                                          std::max( 1.0, std::max( area.windowWidth, area.windowHeight ) / 4.0 ) ) )
          pointOptions.predictedShape = w->searchFromReference;
      m = matchAlongEpipolarBand( *from, pixelInReference, *to, curve, pointOptions );
    }
    else
      m = matchAroundPosition( *from, pixelInReference, *to, *approximateInTarget, mOptions.searchRadiusPx, area );
    return m;
  }

} // namespace geostation

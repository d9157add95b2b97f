/***************************************************************************
  greytiles.cpp - an image's grey levels, one window at a time
 ***************************************************************************/
#include "extraction/greytiles.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "io/rasterfile.h"
#include "matching/matchimage.h"

namespace geostation
{

  GreyTiles::GreyTiles( const cv::Mat &grey )
    : mSize( grey.size() )
    , mWhole( grey )
  {
    if ( grey.empty() || grey.type() != CV_8UC1 )
      throw std::invalid_argument( "line extraction needs an 8-bit single-band image" );
  }

  GreyTiles::GreyTiles( cv::Size size, Reader reader, size_t maxCachedBytes )
    : mSize( size )
    , mReader( std::move( reader ) )
    , mMaxCachedBytes( maxCachedBytes )
  {
    if ( size.width <= 0 || size.height <= 0 )
      throw std::invalid_argument( "an image read in tiles needs a positive size" );
    if ( !mReader )
      throw std::invalid_argument( "an image read in tiles needs a reader" );
  }

  const cv::Mat &GreyTiles::tile( const TileKey &key ) const
  {
    const auto found = mTiles.find( key );
    if ( found != mTiles.end() )
    {
      mRecent.splice( mRecent.begin(), mRecent, found->second.second );
      return found->second.first;
    }
    const cv::Rect rect = cv::Rect( key.second * kTilePx, key.first * kTilePx, kTilePx, kTilePx ) & cv::Rect( cv::Point(), mSize );
    cv::Mat pixels = mReader( rect );
    if ( pixels.type() != CV_8UC1 || pixels.size() != rect.size() )
      throw std::runtime_error( "the image reader returned " + std::to_string( pixels.cols ) + " x " + std::to_string( pixels.rows ) +
                                " pixels of the wrong kind for a tile of " + std::to_string( rect.width ) + " x " + std::to_string( rect.height ) );
    ++mTilesRead;
    mRecent.push_front( key );
    const size_t bytes = pixels.total();
    auto &entry = mTiles[key];
    entry = { std::move( pixels ), mRecent.begin() };
    mCachedBytes += bytes;
    mPeakCachedBytes = std::max( mPeakCachedBytes, mCachedBytes );
    // the least recently used tiles go; the caller copies from this one before asking for the next
    while ( mCachedBytes > mMaxCachedBytes && mRecent.size() > 1 )
    {
      const TileKey oldest = mRecent.back();
      mRecent.pop_back();
      const auto it = mTiles.find( oldest );
      mCachedBytes -= it->second.first.total();
      mTiles.erase( it );
    }
    return entry.first;
  }

  GreyWindow GreyTiles::window( const cv::Rect &rect ) const
  {
    GreyWindow w;
    const cv::Rect clipped = rect & cv::Rect( cv::Point(), mSize );
    w.origin = clipped.tl();
    if ( clipped.empty() )
      return w;
    if ( whole() )
    {
      w.pixels = mWhole( clipped );
      return w;
    }
    w.pixels.create( clipped.size(), CV_8UC1 );
    for ( int tr = clipped.y / kTilePx; tr <= ( clipped.br().y - 1 ) / kTilePx; ++tr )
      for ( int tc = clipped.x / kTilePx; tc <= ( clipped.br().x - 1 ) / kTilePx; ++tc )
      {
        const cv::Rect tileRect( tc * kTilePx, tr * kTilePx, kTilePx, kTilePx );
        const cv::Rect part = tileRect & clipped;
        const cv::Mat &pixels = tile( { tr, tc } );
        pixels( part - tileRect.tl() ).copyTo( w.pixels( part - clipped.tl() ) );
      }
    return w;
  }

  GreyWindow GreyTiles::around( const Eigen::Vector2d &pixelInImage, int radiusPx ) const
  {
    return covering( pixelInImage, pixelInImage, radiusPx );
  }

  GreyWindow GreyTiles::covering( const Eigen::Vector2d &lowerPx, const Eigen::Vector2d &upperPx, int marginPx ) const
  {
    const Eigen::Vector2d lo = lowerPx.cwiseMin( upperPx ), hi = lowerPx.cwiseMax( upperPx );
    if ( !lo.allFinite() || !hi.allFinite() )
      return GreyWindow();
    // clamp before converting: a point far off the image gives an empty window, not an overflow
    const auto clampPx = []( double v ) { return static_cast<int>( std::clamp( v, -1.0e8, 1.0e8 ) ); };
    const int x0 = clampPx( std::floor( lo.x() ) ) - marginPx, y0 = clampPx( std::floor( lo.y() ) ) - marginPx;
    const int x1 = clampPx( std::ceil( hi.x() ) ) + marginPx, y1 = clampPx( std::ceil( hi.y() ) ) + marginPx;
    return window( cv::Rect( cv::Point( x0, y0 ), cv::Point( x1 + 1, y1 + 1 ) ) );
  }

  GreyTiles greyTilesOf( std::shared_ptr<const RasterReader> reader, const std::optional<std::pair<double, double>> &range16, size_t maxCachedBytes )
  {
    if ( !reader )
      throw std::invalid_argument( "no raster to read" );
    const std::optional<std::pair<double, double>> range = reader->eightBit() ? std::nullopt : std::optional( range16 ? *range16 : greyRangeOf( *reader ) );
    return GreyTiles(
      reader->size(),
      [reader, range]( const cv::Rect &rect )
      {
        const cv::Mat pixels = reader->read( rect ).pixels;
        if ( !range )
          return matchingGrey( pixels );
        cv::Mat grey;
        matchingValues( pixels, range ).convertTo( grey, CV_8U ); // as MatchImage::grey(): rounded
        return grey;
      },
      maxCachedBytes );
  }

} // namespace geostation

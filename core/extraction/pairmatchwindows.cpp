/***************************************************************************
  pairmatchwindows.cpp - the matching pixels of a stereo pair, a window at
  a time
 ***************************************************************************/
#include "extraction/pairmatchwindows.h"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "io/rasterfile.h"

namespace geostation
{

  MatchWindowSource matchWindowsOf( std::shared_ptr<const RasterReader> a, std::shared_ptr<const RasterReader> b,
                                    const std::optional<std::pair<double, double>> &rangeA16, const std::optional<std::pair<double, double>> &rangeB16 )
  {
    if ( !a || !b )
      throw std::invalid_argument( "matching windows need both rasters" );
    using Range = std::optional<std::pair<double, double>>;
    const Range rangeA = a->eightBit() ? Range() : Range( rangeA16 ? *rangeA16 : greyRangeOf( *a ) );
    const Range rangeB = b->eightBit() ? Range() : Range( rangeB16 ? *rangeB16 : greyRangeOf( *b ) );
    return [a, b, rangeA, rangeB]( int image, const cv::Rect &window )
    {
      const RasterReader &reader = image == 0 ? *a : *b;
      const cv::Rect held = matchingWindowToRead( window, reader.size() );
      return std::make_shared<const MatchImage>( reader.read( held ).pixels, held.tl(), reader.size(), image == 0 ? rangeA : rangeB );
    };
  }

  PairMatchWindows::PairMatchWindows( MatchWindowSource source, const cv::Size &sizeA, const cv::Size &sizeB, int growPx, long long wholeBelowPixels )
    : mSource( std::move( source ) )
    , mSize { sizeA, sizeB }
    , mGrowPx( std::max( 0, growPx ) )
    , mWholeBelowPixels( wholeBelowPixels )
  {
    if ( !mSource )
      throw std::invalid_argument( "matching windows need a source of pixels" );
    if ( sizeA.width <= 0 || sizeA.height <= 0 || sizeB.width <= 0 || sizeB.height <= 0 )
      throw std::invalid_argument( "matching windows need the images' sizes" );
  }

  PairMatchWindows::PairMatchWindows( const MatchImage &a, const MatchImage &b )
    : mSize { cv::Size( a.width(), a.height() ), cv::Size( b.width(), b.height() ) }
    , mAvailable( !a.empty() && !b.empty() )
  {
    // not owned: aliasing pointers with no deleter
    mCurrent[0] = std::shared_ptr<const MatchImage>( std::shared_ptr<const MatchImage>(), &a );
    mCurrent[1] = std::shared_ptr<const MatchImage>( std::shared_ptr<const MatchImage>(), &b );
  }

  const MatchImage &PairMatchWindows::holding( int image, const cv::Rect &needed, int growPx )
  {
    if ( image != 0 && image != 1 )
      throw std::invalid_argument( "a pair has images 0 and 1" );
    const cv::Rect bounds( cv::Point(), mSize[image] );
    const cv::Rect wanted = needed & bounds;
    if ( mCurrent[image] && mCurrent[image]->holds( wanted ) )
      return *mCurrent[image];
    if ( !mSource )
      return *mCurrent[image]; // whole images: what is not held lies off the image
    mCurrent[image].reset(); // the old window goes before the new one is read
    const int grow = growPx < 0 ? mGrowPx : growPx;
    cv::Rect window = cv::Rect( wanted.x - grow, wanted.y - grow, wanted.width + 2 * grow, wanted.height + 2 * grow ) & bounds;
    // a window of most of the image: the whole image, read once instead of window after window
    if ( 2 * static_cast<long long>( window.area() ) > static_cast<long long>( bounds.area() ) || static_cast<long long>( bounds.area() ) <= mWholeBelowPixels )
      window = bounds;
    std::shared_ptr<const MatchImage> pixels = mSource( image, window );
    ++mWindowsRead;
    if ( !pixels || pixels->width() != mSize[image].width || pixels->height() != mSize[image].height || !pixels->holds( wanted ) )
      throw std::runtime_error( "the image source returned pixels that do not hold the window asked for (" + std::to_string( window.width ) + " x " +
                                std::to_string( window.height ) + " at " + std::to_string( window.x ) + ", " + std::to_string( window.y ) + ")" );
    mCurrent[image] = std::move( pixels );
    mPeakBytes = std::max( mPeakBytes, ( mCurrent[0] ? mCurrent[0]->bytes() : 0 ) + ( mCurrent[1] ? mCurrent[1]->bytes() : 0 ) );
    return *mCurrent[image];
  }

} // namespace geostation

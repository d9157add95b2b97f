/***************************************************************************
  pairmatchwindows.h - the matching pixels of a stereo pair, a window at a
  time
  -------------------------------------------------------------------------
  The 3-D step of road extraction (and the terrain-height estimate) match
  points of image A along epipolar curves in image B. For images too large
  to prepare whole, PairMatchWindows asks a source for prepared windows:
  it keeps the last window of each image and asks for a new one - what a
  match needs, grown by growPx on every side, so that the next points
  along a line fall in it too - only when a match needs pixels it does not
  hold; a window of more than half the image, or any window of a small
  image, becomes the whole image. Over two whole images it asks for
  nothing.
 ***************************************************************************/
#ifndef GEOSTATION_EXTRACTION_PAIRMATCHWINDOWS_H
#define GEOSTATION_EXTRACTION_PAIRMATCHWINDOWS_H

#include <functional>
#include <memory>
#include <optional>
#include <utility>

#include <opencv2/core.hpp>

#include "matching/matchimage.h"

namespace geostation
{

  /**
   * Prepared matching pixels of image 0 (A) or 1 (B) that offer at least
   * `window` (image pixels, within the image): a windowed MatchImage, or
   * the whole image. Read errors propagate.
   */
  using MatchWindowSource = std::function<std::shared_ptr<const MatchImage>( int image, const cv::Rect &window )>;

  class RasterReader;

  /**
   * Windows of two rasters, each read with the margin MatchImage keeps
   * along a window's inner edges; a 16-bit raster's windows scaled by its
   * whole grey range (greyRangeOf(), computed here when not given). Throws
   * std::invalid_argument without both readers.
   */
  MatchWindowSource matchWindowsOf( std::shared_ptr<const RasterReader> a, std::shared_ptr<const RasterReader> b,
                                    const std::optional<std::pair<double, double>> &rangeA16 = std::nullopt,
                                    const std::optional<std::pair<double, double>> &rangeB16 = std::nullopt );

  class PairMatchWindows
  {
    public:
      /**
       * Windows of images of `sizeA` and `sizeB` from `source`; an image of
       * at most `wholeBelowPixels` is asked for whole (once: cheaper than
       * many windows, and small). Throws std::invalid_argument for empty
       * sizes or no source.
       */
      PairMatchWindows( MatchWindowSource source, const cv::Size &sizeA, const cv::Size &sizeB, int growPx = 384, long long wholeBelowPixels = 4LL << 20 );

      //! Two whole images (not copied: they must outlive this); empty images: no area matching.
      PairMatchWindows( const MatchImage &a, const MatchImage &b );

      //! Whether there are pixels to match at all.
      bool available() const { return mAvailable; }
      cv::Size size( int image ) const { return mSize[image]; }

      /**
       * Pixels of `image` offering `needed` (clipped to the image): the last
       * window when it does, else a new one grown by `growPx` (negative: the
       * growth given at construction; 0 for isolated points, whose
       * neighbours lie far off). Throws std::runtime_error if the source
       * returns pixels that do not offer what was asked for.
       */
      const MatchImage &holding( int image, const cv::Rect &needed, int growPx = -1 );

      //! Windows asked of the source so far.
      long windowsRead() const { return mWindowsRead; }
      //! The largest pixel data held at once (bytes, both images).
      size_t peakBytes() const { return mPeakBytes; }

    private:
      MatchWindowSource mSource;
      cv::Size mSize[2];
      std::shared_ptr<const MatchImage> mCurrent[2];
      int mGrowPx = 0;
      long long mWholeBelowPixels = 0;
      bool mAvailable = true;
      long mWindowsRead = 0;
      size_t mPeakBytes = 0;
  };

} // namespace geostation

#endif // GEOSTATION_EXTRACTION_PAIRMATCHWINDOWS_H

/***************************************************************************
  matchimage.h - an image prepared for area-based matching
  -------------------------------------------------------------------------
  Matching works on one grey channel: RGB is reduced to luminance, 16-bit
  is scaled linearly from its own range to 0..255 (kept in floating point
  for least-squares matching, rounded for correlation). The central-
  difference gradients of thesis eqs. 5.12-5.13 are computed once.

  Pixel convention (docs/conventions.md §1): the value of pixel (i, j) belongs to
  its centre (i + 0.5, j + 0.5); sampleAt() interpolates bilinearly between
  centres (thesis eq. 5.15).

  A match image may hold a window of a larger image only (an image too
  large to prepare whole: 9 bytes a pixel). Every coordinate stays the
  whole image's; width() and height() are the whole image's, and
  holds() / canSample() say which pixels are there. Along the window's
  inner edges kWindowMarginPx pixels are held but not offered (the
  B-spline prefilter sees the window's edge there), so a windowed image
  samples exactly like the whole one.
 ***************************************************************************/
#ifndef GEOSTATION_MATCHING_MATCHIMAGE_H
#define GEOSTATION_MATCHING_MATCHIMAGE_H

#include <optional>
#include <utility>

#include <Eigen/Core>
#include <opencv2/core.hpp>

namespace geostation
{

  class MatchImage
  {
    public:
      //! Pixels held along a window's inner edges but not offered (the prefilter's reach, below 1e-3 of a grey value).
      static constexpr int kWindowMarginPx = 8;

      MatchImage() = default;
      /**
       * From an 8- or 16-bit image with 1, 3 (RGB) or 4 (RGBA) channels.
       * Throws std::invalid_argument for anything else.
       */
      explicit MatchImage( const cv::Mat &image );

      /**
       * From the pixels `window` of an image of `imageSize` whose top-left
       * pixel is `origin` (image pixels). A 16-bit window is scaled by
       * `range` - the whole image's grey range (greyRangeOf()), so that its
       * values are the whole image's - or, without it, by its own range.
       * Throws std::invalid_argument like the above, or if the window does
       * not lie in the image.
       */
      MatchImage( const cv::Mat &window, const cv::Point &origin, const cv::Size &imageSize,
                  const std::optional<std::pair<double, double>> &range = std::nullopt );

      //! The whole image's size, windowed or not.
      int width() const { return mImageSize.width; }
      int height() const { return mImageSize.height; }
      bool empty() const { return mGrey.empty(); }
      //! Whether only a window of the image is held.
      bool windowed() const { return mOffered != cv::Rect( 0, 0, mImageSize.width, mImageSize.height ); }
      //! The pixels offered (image pixels): the whole image, or the window less its inner margins.
      const cv::Rect &offered() const { return mOffered; }
      //! Whether all these pixels (image pixels) are offered.
      bool holds( const cv::Rect &pixels ) const { return ( pixels & mOffered ) == pixels; }
      //! Bytes of pixel data it holds (grey, values and spline coefficients: 9 a pixel).
      size_t bytes() const { return mGrey.total() * mGrey.elemSize() + mValue.total() * mValue.elemSize() + mCoefficients.total() * mCoefficients.elemSize(); }

      //! The pixels held (CV_8U for correlation, CV_32F 0..255); pixel (0, 0) is image pixel origin().
      const cv::Mat &grey() const { return mGrey; }
      const cv::Mat &value() const { return mValue; }
      const cv::Point &origin() const { return mOrigin; }
      //! Grey values from image pixel (col, row) on along its row (the caller checks holds()).
      const uint8_t *greyAt( int col, int row ) const { return mGrey.ptr<uint8_t>( row - mOrigin.y ) + ( col - mOrigin.x ); }
      //! The value of image pixel (col, row) (the caller checks holds()).
      float valueAt( int col, int row ) const { return mValue.at<float>( row - mOrigin.y, col - mOrigin.x ); }
      //! Values of the image pixels `pixels` (the caller checks holds()).
      cv::Mat valueIn( const cv::Rect &pixels ) const { return mValue( pixels - mOrigin ); }
      //! Whether (col, row) lies between the outermost pixel centres offered.
      bool canSample( double col, double row ) const
      {
        return col >= mOffered.x + 0.5 && row >= mOffered.y + 0.5 && col <= mOffered.br().x - 0.5 && row <= mOffered.br().y - 0.5;
      }

      //! Whether bicubic samples at (col, row) stay inside the pixels offered (one more pixel than bilinear).
      bool canSampleCubic( double col, double row ) const
      {
        return col >= mOffered.x + 1.5 && row >= mOffered.y + 1.5 && col <= mOffered.br().x - 2.5 && row <= mOffered.br().y - 2.5;
      }

      /**
       * Cubic B-spline interpolation (of prefiltered coefficients: it passes
       * through the pixel values) and its derivatives along col and row at a
       * continuous pixel position (caller checks canSampleCubic()).
       */
      float sampleCubic( double col, double row, float *dCol = nullptr, float *dRow = nullptr ) const;

      /**
       * Bilinear interpolation between pixel centres (thesis eq. 5.15), and
       * its slope along col and row as the difference across one pixel
       * (half a pixel either side; the caller checks canSampleCubic()).
       */
      float sampleBilinear( double col, double row, float *dCol = nullptr, float *dRow = nullptr ) const;

    private:
      void prepare( const cv::Mat &image, const std::optional<std::pair<double, double>> &range = std::nullopt );

      cv::Mat mGrey, mValue;
      cv::Mat mCoefficients; //!< cubic B-spline coefficients of mValue
      cv::Point mOrigin { 0, 0 };   //!< image pixel of the held pixels' (0, 0)
      cv::Size mImageSize { 0, 0 }; //!< the whole image
      cv::Rect mOffered;            //!< image pixels offered
  };

  /**
   * The grey levels matching makes of an image: 1 channel as it is, RGB or
   * RGBA to grey (8- or 16-bit, as the input). Throws std::invalid_argument
   * for anything else.
   */
  cv::Mat matchingGrey( const cv::Mat &image );

  /**
   * Matching's grey values of an image (CV_32F, 0..255): matchingGrey(),
   * a 16-bit image scaled by `range` (the whole image's) or by its own
   * range. MatchImage::grey() is these rounded to 8 bits.
   */
  cv::Mat matchingValues( const cv::Mat &image, const std::optional<std::pair<double, double>> &range = std::nullopt );

  /**
   * The pixels to read for a windowed MatchImage that offers `offered`:
   * `offered` with MatchImage::kWindowMarginPx around it, within the image.
   */
  cv::Rect matchingWindowToRead( const cv::Rect &offered, const cv::Size &imageSize );

  class RasterReader;

  /**
   * The range of the grey levels of a whole raster (what MatchImage scales a
   * 16-bit image by), read strip by strip (bounded memory). Throws like
   * RasterReader::read().
   */
  std::pair<double, double> greyRangeOf( const RasterReader &reader );

} // namespace geostation

#endif // GEOSTATION_MATCHING_MATCHIMAGE_H

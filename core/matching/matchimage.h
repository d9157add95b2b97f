/***************************************************************************
  matchimage.h - an image prepared for area-based matching
  -------------------------------------------------------------------------
  Matching works on one grey channel: RGB is reduced to luminance, 16-bit
  is scaled linearly from its own range to 0..255 (kept in floating point
  for least-squares matching, rounded for correlation). The central-
  difference gradients of thesis eqs. 5.12-5.13 are computed once.

  Pixel convention (CONVENTIONS §1): the value of pixel (i, j) belongs to
  its centre (i + 0.5, j + 0.5); sampleAt() interpolates bilinearly between
  centres (thesis eq. 5.15).
 ***************************************************************************/
#ifndef GEOSTATION_MATCHING_MATCHIMAGE_H
#define GEOSTATION_MATCHING_MATCHIMAGE_H

#include <Eigen/Core>
#include <opencv2/core.hpp>

namespace geostation
{

  class MatchImage
  {
    public:
      MatchImage() = default;
      /**
       * From an 8- or 16-bit image with 1, 3 (RGB) or 4 (RGBA) channels.
       * Throws std::invalid_argument for anything else.
       */
      explicit MatchImage( const cv::Mat &image );

      int width() const { return mGrey.cols; }
      int height() const { return mGrey.rows; }
      bool empty() const { return mGrey.empty(); }
      //! Bytes of pixel data it holds (grey, values and spline coefficients: 9 a pixel).
      size_t bytes() const { return mGrey.total() * mGrey.elemSize() + mValue.total() * mValue.elemSize() + mCoefficients.total() * mCoefficients.elemSize(); }

      const cv::Mat &grey() const { return mGrey; }     //!< CV_8U, for correlation
      const cv::Mat &value() const { return mValue; }   //!< CV_32F, 0..255
      //! Whether (col, row) lies between the outermost pixel centres.
      bool canSample( double col, double row ) const
      {
        return col >= 0.5 && row >= 0.5 && col <= mGrey.cols - 0.5 && row <= mGrey.rows - 0.5;
      }

      //! Whether bicubic samples at (col, row) stay inside the image (one more pixel than bilinear).
      bool canSampleCubic( double col, double row ) const
      {
        return col >= 1.5 && row >= 1.5 && col <= mGrey.cols - 2.5 && row <= mGrey.rows - 2.5;
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
      cv::Mat mGrey, mValue;
      cv::Mat mCoefficients; //!< cubic B-spline coefficients of mValue
  };

} // namespace geostation

#endif // GEOSTATION_MATCHING_MATCHIMAGE_H

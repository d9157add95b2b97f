/***************************************************************************
  similarity.h - correlation measures of area-based matching (thesis §5.1.1)
  -------------------------------------------------------------------------
  cc    cross-correlation coefficient            (eq. 5.1)
  ncc   normalised cross-correlation             (eq. 5.2)
  wcc   weighted cross-correlation               (eq. 5.3)
  wncc  weighted normalised cross-correlation    (eq. 5.4)
  Windows are w x h pixels (odd sizes: square 15 x 15, or rectangular such as
  3 x 15 for road lines), centred on a pixel. The weights of wcc and wncc
  fall from 5 at the centre to 2 at the border, as in Xin's (1995) 5 x 5
  example (Figure 5.2): w = 2 + 3 (1 - r)^2, r the normalised ring.
  cc and ncc run on integer sums (exact, vectorised); the sub-pixel peak is
  the parabola through the best score and its neighbours (eqs. 5.5-5.6).
 ***************************************************************************/
#ifndef GEOSTATION_MATCHING_SIMILARITY_H
#define GEOSTATION_MATCHING_SIMILARITY_H

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "matching/matchimage.h"

namespace geostation
{

  enum class SimilarityMeasure
  {
    CC,
    NCC,
    WCC,
    WNCC,
  };

  std::string similarityMeasureName( SimilarityMeasure measure );
  //! Parses "cc", "ncc", "wcc" or "wncc"; nothing otherwise.
  std::optional<SimilarityMeasure> similarityMeasureFromName( const std::string &name );

  //! The weight of a window pixel at offset (dx, dy) from the centre of a w x h window.
  double centreWeight( int dx, int dy, int width, int height );

  /**
   * The target window of the reference image, ready to be compared with
   * windows of other images. Invalid (with a reason) when the window leaves
   * the image, the sizes are not odd, or it has no texture.
   */
  class CorrelationTemplate
  {
    public:
      CorrelationTemplate( const MatchImage &image, int centreCol, int centreRow, int width, int height, SimilarityMeasure measure );

      /**
       * A window of another shape: the w x h grid of offsets (u, v) from the
       * centre, mapped into `image` as pixelInImage + imageFromWindow (u, v)
       * and sampled bilinearly. With imageFromWindow the inverse of a
       * predicted search-from-reference shape, the template shows the
       * reference patch as the search image is expected to show it, centred
       * exactly on pixelInImage (not on a pixel centre).
       */
      CorrelationTemplate( const MatchImage &image, const Eigen::Vector2d &pixelInImage, const Eigen::Matrix2d &imageFromWindow, int width, int height,
                           SimilarityMeasure measure );

      bool valid() const { return mReason.empty(); }
      const std::string &reason() const { return mReason; }
      //! Invalid because the window has no texture (rather than leaving the image or a bad size).
      bool flat() const { return mFlat; }
      int width() const { return mWidth; }
      int height() const { return mHeight; }
      SimilarityMeasure measure() const { return mMeasure; }
      //! Standard deviation of the template's grey values.
      double contrast() const { return mContrast; }

      /**
       * The score against the window of `search` centred on pixel
       * (centreCol, centreRow); nothing when that window leaves the image or
       * has no texture. Scores lie in [-1, 1] (cc, wcc: [0, 1] for grey values).
       */
      std::optional<double> score( const MatchImage &search, int centreCol, int centreRow ) const;

      /**
       * Dense matching: the scores of the windows centred on every pixel of
       * `centres` (a rectangle of centre pixels of `search`), as a CV_64F
       * matrix of centres.height rows and centres.width columns, NaN where
       * score() gives nothing. Equal to score() at every position; cc and ncc
       * take the window sums from an integral image and correlate only the
       * cross term per position, so they cost about a third of calling
       * score() everywhere.
       */
      cv::Mat scoreArea( const MatchImage &search, const cv::Rect &centres ) const;

    private:
      //! Takes the grey values (row by row) and prepares sums, padding and weights.
      void setValues( std::vector<int> values );
      //! cc / ncc from the integer sums of a window: cross term, sum and sum of squares.
      std::optional<double> integerScore( int64_t st, int64_t s, int64_t ss ) const;

      int mWidth, mHeight;
      SimilarityMeasure mMeasure;
      std::string mReason;
      bool mFlat = false;
      std::vector<int> mValues;     //!< template grey values, row by row
      int mPaddedWidth = 0;         //!< row length rounded up to 16, for the vectorised kernel
      std::vector<int16_t> mPadded; //!< values padded with zeros to mPaddedWidth per row
      std::vector<int16_t> mMask;   //!< all bits set on the window's columns, 0 on the padding
      std::vector<double> mWeights; //!< weighted measures
      double mSum = 0, mSumSq = 0;  //!< of the values (weighted for wcc/wncc)
      double mWeightSum = 0;
      double mContrast = 0;
  };

  //! The sub-pixel offset of a peak from three scores at -1, 0, +1 (eq. 5.6); 0 when not a peak.
  double parabolaPeakOffset( double before, double at, double after );

} // namespace geostation

#endif // GEOSTATION_MATCHING_SIMILARITY_H

/***************************************************************************
  areamatcher.h - finding the conjugate point (thesis §5.1-5.3)
  -------------------------------------------------------------------------
  Correlation along the epipolar band: candidate windows centred on the
  pixels of the epipolar curve (the segment for the depth range) and on
  its parallels up to bandHalfWidthPx away (Xin (1995) searches the line
  and its two neighbours, as the orientation is not perfect). Optionally
  Xin's (1995) jump rule: below 0.2 / 0.4 / 0.6 the search skips 4 / 3 / 2
  pixels. Or a 2-D search around an approximate position, for unoriented
  pairs. The best score is refined to sub-pixel by parabolas (eqs. 5.5-5.6)
  and then, optionally, by least-squares matching; where LSM cannot refine
  (a line or an edge, whose shift along itself it cannot fix) the
  correlation peak stands with sigma 0.5 px and the reason is kept.
  Expected failures (window outside, flat texture, score below the
  threshold) give a result with matched = false and a reason.
 ***************************************************************************/
#ifndef GEOSTATION_MATCHING_AREAMATCHER_H
#define GEOSTATION_MATCHING_AREAMATCHER_H

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "matching/leastsquaresmatching.h"
#include "matching/similarity.h"

namespace geostation
{

  /**
   * What a match is (docs/conventions.md §8): least squares converged and passed its
   * checks; a correlation peak only (LSM off, or not applicable on a line or
   * an edge); or why there is no match.
   */
  enum class MatchStatus
  {
    Lsm,
    Correlation,
    NoPeak,       //!< no window to correlate, or the best correlation below the threshold
    Ambiguous,    //!< a second peak (almost) as good, and least squares did not decide
    Diverged,     //!< least squares went astray, or its fit or shape is implausible
    Inconsistent, //!< matching back from the found point does not return to the reference point
    Outside,      //!< the point or its window leaves an image
  };

  //! "lsm", "correlation", "no_peak", "ambiguous", "diverged", "inconsistent", "outside"
  std::string matchStatusName( MatchStatus status );

  //! Lsm and Correlation are matches; the other statuses say why there is none.
  inline bool isMatch( MatchStatus status ) { return status == MatchStatus::Lsm || status == MatchStatus::Correlation; }

  struct AreaMatchOptions
  {
    SimilarityMeasure measure = SimilarityMeasure::NCC;
    int windowWidth = 15;       //!< odd; 15 x 15 in general, 15 x 3 (w x h) for road lines
    int windowHeight = 15;
    double minScore = 0.7;      //!< below it: no match
    int bandHalfWidthPx = 1;    //!< parallels searched on each side of the epipolar curve
    bool jumpRule = false;      //!< Xin's (1995) 4 / 3 / 2 pixel jumps below 0.2 / 0.4 / 0.6
    bool lsm = true;            //!< refine by least-squares matching
    LsmOptions lsmOptions;
    /**
     * Least squares is started from this many places - the correlation
     * peak, the approximate position (2-D search) and the next separate
     * peaks - and the converged solution with the smallest sigma0 kept.
     */
    int lsmStarts = 4;
    //! Least squares is matched back from the found point to the reference; farther than this (px) from it: inconsistent.
    bool backMatch = true;
    double consistencyPx = 0.5;
    //! sigma0 of least squares over the window's grey-value standard deviation above this: diverged (a poor fit).
    double maxSigma0Ratio = 0.4;
    //! At or below this ratio the fit is close and no further start is tried.
    double goodFitRatio = 0.2;
    //! The affine shape's scales outside [1 / maxAffineScale, maxAffineScale]: diverged.
    double maxAffineScale = 3.0;
    //! A peak below minScore still gets least squares from the approximate position (2-D search), whose checks decide.
    bool lsmBelowThreshold = true;
    //! Window scales least squares starts from when no start converged with the same scale (strong scale differences).
    std::vector<double> fallbackScales { 2.0, 0.5 };
    /**
     * 2-D search: a correlation maximum on the border of the search area is
     * no peak (the true one may lie outside); the best peak inside it is
     * taken, and without one least squares starts from the approximate
     * position as for a weak peak. Off for areas of a pixel or two that
     * only refine a peak found before.
     */
    bool borderIsNoPeak = true;
    //! A correlation-only match whose second peak scores within this of the best: ambiguous.
    double ambiguityMargin = 0.05;
    /**
     * The window's shape in the search image predicted from the geometry
     * (predictWindowShape(): search pixels per reference pixel), for
     * oblique and close-range pairs. Correlation then compares the search
     * windows both with the square reference window and with the reference
     * patch resampled into the predicted shape, and keeps the template that
     * correlates better (a point off the predicted surface - a pole above the
     * road - keeps the square one); least squares starts from the winning
     * shape, and the shape check is made relative to it.
     */
    std::optional<Eigen::Matrix2d> predictedShape;

    //! Throws std::invalid_argument with one sentence for even or oversized windows, a threshold outside [-1, 1] or a negative band.
    void check() const;
  };

  struct AreaMatch
  {
    MatchStatus status = MatchStatus::NoPeak;
    std::string message;                                   //!< why not, when not matched (or why LSM did not refine)
    Eigen::Vector2d pixelInImage = Eigen::Vector2d::Zero(); //!< the conjugate point (best guess even when not matched)
    double score = 0.0;                                    //!< best correlation
    double secondScore = 0.0;                              //!< best correlation of a separate peak (ambiguity)
    Eigen::Vector2d correlationPixel = Eigen::Vector2d::Zero(); //!< after the parabola, before LSM
    double sigmaPx = 0.0;                                  //!< LSM's larger shift sigma, or 0.5 px for a correlation peak
    int candidates = 0;                                    //!< windows correlated
    //! The best separate peaks (more than 2.5 px apart), best first, as conjugate-point pixels (integer precision)
    std::vector<std::pair<Eigen::Vector2d, double>> peaks;
    LsmResult lsm;
    bool shapedWindow = false;                             //!< the predicted shape's template correlated better than the square one

    //! Least squares or a correlation peak: a match (docs/conventions.md §8).
    bool matched() const { return isMatch( status ); }
  };

  /**
   * Searches `search` along `curve` (pixels of the epipolar curve, e.g.
   * densified by epipolarCurve(), in order of depth) for the point of
   * `reference` at `pixelInReference`.
   */
  AreaMatch matchAlongEpipolarBand( const MatchImage &reference, const Eigen::Vector2d &pixelInReference, const MatchImage &search,
                                    const std::vector<Eigen::Vector2d> &curve, const AreaMatchOptions &options );

  //! Searches every pixel within `radiusPx` of `approximate` (2-D search, no orientation needed).
  AreaMatch matchAroundPosition( const MatchImage &reference, const Eigen::Vector2d &pixelInReference, const MatchImage &search,
                                 const Eigen::Vector2d &approximate, double radiusPx, const AreaMatchOptions &options );

} // namespace geostation

#endif // GEOSTATION_MATCHING_AREAMATCHER_H

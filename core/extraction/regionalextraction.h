/***************************************************************************
  regionalextraction.h - REM, the regional extraction method (report §4.1)
  -------------------------------------------------------------------------
  REM continues where LEM broke off (occlusion, shadow, a junction, worn
  surface): it looks at a rectangular area of interest ahead of the break
  (sample lines, confidence values, semi-threshold, collinearity
  relaxation; see areaofinterest.h) and follows the chain of confirmed
  points from the last known point. It accepts more distortion than LEM
  and hands back to LEM as soon as the line is ideal again. It stops at
  the image border, at a known line (joined), or where no chain continues
  (final break-off).
 ***************************************************************************/
#ifndef GEOSTATION_EXTRACTION_REGIONALEXTRACTION_H
#define GEOSTATION_EXTRACTION_REGIONALEXTRACTION_H

#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "extraction/areaofinterest.h"
#include "extraction/localextraction.h"

namespace geostation
{

  struct RemOptions
  {
    double areaLengthPx = 0.0;    //!< 0: 5 x the line's width, at least 40 px
    double areaHalfWidthPx = 0.0; //!< 0: 0.75 x the line's width, at least 6 px
    double spacingPx = 0.0;       //!< 0: a third of the line's width, within 2..4 px
    double semiThreshold = 0.35;
    int candidatesPerLine = 3;
    int relaxationIterations = 3;
    double confirmThreshold = 0.3;
    double maxAngleDeg = 15.0;
    double maxGapPx = 0.0;           //!< a gap the chain may bridge; 0: twice the line's width
    double minChainConfidence = 0.5; //!< mean confidence of an accepted chain
    int maxAreas = 6;                //!< consecutive areas before REM gives up on a line that never becomes ideal

    //! Throws std::invalid_argument naming the first bad value.
    void check() const;
    //! The area of interest REM lays ahead of a line state.
    AreaOfInterest areaAhead( const LineState &state ) const;
    //! The analysis options for a line of this state.
    AreaAnalysisOptions analysis( const LineState &state, int polarity ) const;
  };

  struct RemSummary
  {
    std::vector<Eigen::Vector2d> pixels; //!< the start, then the chain's points (and the join, if any)
    LineState end;
    DeadEndKind stop = DeadEndKind::FinalBreakOff; //!< Ideal: LEM can go on from `end`
    int areas = 0;
  };

  //! Continues the line from a break-off dead end. The matrix is read only.
  RemSummary followRegionally( const cv::Mat &grey, const ResultMatrix &matrix, const LineState &start, const LineObjectOptions &object,
                               const LemOptions &lem, const RemOptions &options );

  /**
   * The band nearest to `pixelInImage` across `direction` within `searchPx`
   * (width 0.6-1.6 x `widthPx`, contrast at least half the minimum): its
   * centre, or nothing.
   */
  std::optional<CrossSection> refineAcross( const cv::Mat &grey, const Eigen::Vector2d &pixelInImage, const Eigen::Vector2d &direction, double widthPx,
                                            const LineObjectOptions &object, double searchPx );

} // namespace geostation

#endif // GEOSTATION_EXTRACTION_REGIONALEXTRACTION_H

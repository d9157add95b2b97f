/***************************************************************************
  localextraction.h - LEM, the local extraction method (report §3, §4.1)
  -------------------------------------------------------------------------
  From a point on the line and its direction, LEM predicts the next point
  one step ahead, verifies it on a grey-level profile across the predicted
  direction (a band of about the measured width and contrast, near the
  prediction), accepts it and adapts width, contrast and direction to what
  it measured. It works conservatively: a step whose profile does not
  comply ends it. It stops at
  - the image border (final dead end),
  - a line already in the result matrix, ahead within about the line's
    width (final dead end, joined to that line),
  - a distortion it cannot pass (break-off dead end, for REM).
 ***************************************************************************/
#ifndef GEOSTATION_EXTRACTION_LOCALEXTRACTION_H
#define GEOSTATION_EXTRACTION_LOCALEXTRACTION_H

#include <optional>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "extraction/crossprofile.h"
#include "extraction/linestate.h"
#include "extraction/resultmatrix.h"

namespace geostation
{

  struct LemOptions
  {
    double stepPx = 0.0;          //!< 0: the line's width, within 4..12 px
    double maxTurnDeg = 20.0;     //!< direction change accepted per step
    double widthTolerance = 0.4;  //!< a step's width within (1 +- this) x the line's width
    double contrastFraction = 0.4; //!< a step's contrast at least this fraction of the line's (and the minimum contrast)
    double searchPx = 0.0;        //!< 0: 0.35 x width + 1.5 px either side of the prediction
    int maxSteps = 100000;
    //! Steps through a junction's mouth (one side of the band open), at most this many widths of line in a row.
    double openSideWidths = 2.0;

    //! Throws std::invalid_argument naming the first bad value.
    void check() const;
  };

  struct LemSummary
  {
    std::vector<Eigen::Vector2d> pixels; //!< the start, then one point per accepted step (and the join, if any)
    LineState end;                       //!< the last accepted point
    DeadEndKind stop = DeadEndKind::BreakOff;
    int steps = 0;
  };

  /**
   * Follows the line from `start`. The result matrix is read only (known
   * roads); the caller draws the result.
   */
  LemSummary followLocally( const cv::Mat &grey, const ResultMatrix &matrix, const LineState &start, const LineObjectOptions &object,
                            const LemOptions &options );

  /**
   * One LEM step from `from`: the next point and the line's state there, or
   * nothing when the profile does not comply. Used by REM to decide that
   * the line is ideal again. With `openSide`, a band of the line's width
   * open on one side (a junction's mouth) complies within 1.5 px of the
   * prediction; direction, width and contrast are then kept.
   */
  std::optional<LineState> localStep( const cv::Mat &grey, const LineState &from, const LineObjectOptions &object, const LemOptions &options,
                                      bool openSide = false );

  //! The step LEM takes for a line of this width.
  double lemStepPx( const LemOptions &options, double widthPx );

  //! Whether a point is too close to the border to take a profile of a line this wide.
  bool nearImageBorder( const cv::Mat &grey, const Eigen::Vector2d &pixelInImage, double widthPx );
  //! The same for an image of `size`.
  bool nearImageBorder( const cv::Size &size, const Eigen::Vector2d &pixelInImage, double widthPx );

  /**
   * A known line ahead: the nearest result-matrix pixel within `radiusPx` of
   * `pixelInImage` that lies ahead of `behind` along `direction` (more than
   * `minAheadPx`), or nothing.
   */
  std::optional<Eigen::Vector2d> knownLineAhead( const ResultMatrix &matrix, const Eigen::Vector2d &pixelInImage, const Eigen::Vector2d &behind,
                                                 const Eigen::Vector2d &direction, double radiusPx, double minAheadPx );

} // namespace geostation

#endif // GEOSTATION_EXTRACTION_LOCALEXTRACTION_H

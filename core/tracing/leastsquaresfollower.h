/***************************************************************************
  leastsquaresfollower.h - least-squares line following (thesis §6.3.2)
  -------------------------------------------------------------------------
  The line is followed row by row (column by column for a line closer to
  the rows): a window two rows high and wider than the line is matched one
  row further on with a horizontal shift only (eqs. 6.9-6.15), by Gauss-
  Newton iterations with linear resampling along the row (eq. 6.14) and
  the central-difference gradient of eq. 6.9. Two radiometric parameters
  (brightness and contrast) are added so shadows across the line do not
  pull the shift. The target is the line's own profile, averaged over the
  rows followed (each aligned window adds a fraction), so it narrows with
  the line and does not drift as a pure row-to-row chain would. Each
  point carries the sigma of its shift.
 ***************************************************************************/
#ifndef GEOSTATION_TRACING_LEASTSQUARESFOLLOWER_H
#define GEOSTATION_TRACING_LEASTSQUARESFOLLOWER_H

#include "tracing/linetrace.h"

namespace geostation
{

  struct LeastSquaresFollowOptions
  {
    FollowOptions follow;
    int windowHalfWidthPx = 5;   //!< at least: Xin's (1995) 11-pixel rows; stripes get 1.25 x their width + 3
    int maxIterations = 10;
    double convergencePx = 0.01; //!< |dx| that ends the iterations
    double maxShiftPx = 2.0;     //!< from the predicted position: larger means the line is lost
    double minCorrelation = 0.7; //!< of target and matched window
    double templateUpdate = 0.3; //!< weight of each new aligned window in the target
  };

  FollowResult followLeastSquares( const cv::Mat &grey, const FollowRequest &request, const LeastSquaresFollowOptions &options = LeastSquaresFollowOptions() );

} // namespace geostation

#endif // GEOSTATION_TRACING_LEASTSQUARESFOLLOWER_H

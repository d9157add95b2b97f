/***************************************************************************
  polynomialfollower.h - polynomial edge fitting (thesis §6.3.3, §6.5.2)
  -------------------------------------------------------------------------
  A strip along the current direction (50 px long, a few pixels either
  side) collects the line's candidate points, one per cross-section; a
  second-order polynomial v = k0 + k1 u + k2 u^2 across the strip (u along
  it) is fitted by least squares (eqs. 6.16-6.20). If k2 bends the strip by
  less than half a pixel the line is straight and the linear fit is kept.
  The second pass drops candidates whose residual exceeds the threshold and
  fits again. Interval points are taken every 35 px on straight strips and
  every 20 px on curved ones (§6.5.2); the next strip starts at the last
  supported point along the fitted tangent. No skeleton is needed, so
  dashed lines, worn paint and shadows are handled as long as a strip has
  support.
 ***************************************************************************/
#ifndef GEOSTATION_TRACING_POLYNOMIALFOLLOWER_H
#define GEOSTATION_TRACING_POLYNOMIALFOLLOWER_H

#include "tracing/linetrace.h"

namespace geostation
{

  struct PolynomialFollowOptions
  {
    FollowOptions follow;
    int stripLengthPx = 50;
    double stripHalfWidthPx = 4.0;
    double minSupport = 0.3;          //!< fraction of the strip's cross-sections with a candidate
    double straightTolerancePx = 0.5; //!< k2 (L/2)^2 below this: straight
    double outlierPx = 1.0;           //!< second pass: residual threshold (at least 2.5 sigma)
    int intervalStraightPx = 35;
    int intervalCurvedPx = 20;
    double correlatedFraction = 0.45; //!< a point's sigma is at least this times the candidates' scatter
  };

  FollowResult followPolynomial( const cv::Mat &grey, const FollowRequest &request, const PolynomialFollowOptions &options = PolynomialFollowOptions() );

} // namespace geostation

#endif // GEOSTATION_TRACING_POLYNOMIALFOLLOWER_H

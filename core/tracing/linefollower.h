/***************************************************************************
  linefollower.h - one road line through one image, gaps bridged
  -------------------------------------------------------------------------
  Runs one of the followers from a start on the line. Where the follower
  loses the line (the end of a dash, worn paint, a parked car in front of
  the kerb) the line is extrapolated straight ahead - a straight road line
  stays straight in a photo - and looked for on cross-sections a few
  pixels apart, with a tolerance that grows with the distance; found and
  confirmed a little further on and with the grey levels beside it that
  the line had before the gap, following resumes there. The gap may be
  as long as maxGapM on the ground (or maxGapPx without a ground model).
  The followed pixels are then reduced to vertices by Douglas-Peucker
  (§6.4).
 ***************************************************************************/
#ifndef GEOSTATION_TRACING_LINEFOLLOWER_H
#define GEOSTATION_TRACING_LINEFOLLOWER_H

#include <functional>

#include "tracing/directionalfollower.h"
#include "tracing/leastsquaresfollower.h"
#include "tracing/polynomialfollower.h"

namespace geostation
{

  struct LineFollowOptions
  {
    DirectionalOptions directional;
    LeastSquaresFollowOptions leastSquares;
    PolynomialFollowOptions polynomial;
    double maxGapM = 12.0;            //!< longest gap bridged on the ground (a 9 m dash gap and some)
    double maxGapPx = 300.0;          //!< without a ground model
    double vertexTolerancePx = 0.4;   //!< Douglas-Peucker tolerance of the vertices
    /**
     * A line found beyond a gap must have on its sides what the line had over
     * the last 100 px before it (sidesAgree() within this fraction of the line's
     * contrast there, and 4 grey levels): an obstacle's outline, a kerb's outer
     * edge or a passer-by's feet on the line's course are not taken for it.
     * 0 takes any line of the profile.
     */
    double sideTolerance = 0.15;
    /**
     * Least squares: a line found beyond a gap is taken only where the
     * follower then follows it for at least this many pixels; otherwise the
     * gap goes on (its length counted from where the line was last
     * followed), and such hits at the end of the line are dropped where the
     * line is lost after them (not where the image or the distance limit
     * ends it). The skeleton and the polynomial strips follow nothing of a
     * small far dash they bridge to, so for them every hit counts.
     */
    double minLegPx = 2.0;
    /**
     * Ground distance (metres) between two pixels of the image, e.g. through
     * the road plane; nothing where a pixel does not reach the ground.
     */
    std::function<std::optional<double>( const Eigen::Vector2d &, const Eigen::Vector2d & )> groundDistanceM;
  };

  struct LineFollowResult
  {
    FollowResult line;          //!< vertices (after Douglas-Peucker), sigmas, stop, pixels followed
    int bridgedGaps = 0;
    double bridgedPx = 0.0;
  };

  //! One method (not Auto) from request.start; see the file comment.
  LineFollowResult followLine( const cv::Mat &grey, const FollowRequest &request, TraceMethod method, const LineFollowOptions &options = LineFollowOptions() );

  /**
   * followLine() both ways from request.start, as from an operator's click in
   * the middle of a line: the part behind the start (followed along
   * -request.direction, an edge's polarity turned with it) joined before the
   * part ahead, in request.direction's order. stop, profile and direction are
   * those of the part ahead; pixels followed and gaps bridged are summed.
   */
  LineFollowResult followLineBothWays( const cv::Mat &grey, const FollowRequest &request, TraceMethod method, const LineFollowOptions &options = LineFollowOptions() );

} // namespace geostation

#endif // GEOSTATION_TRACING_LINEFOLLOWER_H

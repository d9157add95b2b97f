/***************************************************************************
  multistationvertices.h - traced vertices seen from the stations before
  -------------------------------------------------------------------------
  Xin's (1995) own conclusion (§7): multi-image intersection improves the
  accuracy. A road line traced at station k was seen 10-30 m further away
  from the stations before it, in both of their images, each station with
  a GNSS/INS pose error of its own. refineFromOtherStations() looks for the
  line where each vertex of station k projects into those images (the line
  located on a profile across it, as the followers do) and adjusts the
  vertex from all of it:

  - station k: the reference point (col, row) and the partner's line at
    the epipolar crossing (one observation across the line: along a line
    there is nothing to measure);
  - each other station: one observation across the line in each image.

  A vertex that the others see but mostly do not find the line at, where
  they confirm the station's other vertices, is left out (see
  MultiStationOptions::minLooksToConfirm).

  Generalised least squares with the observations of one station
  correlated through that station's pose sigmas (the rig moves as a
  whole: rigPoseCovariance()), so the vertex's covariance is its marginal
  one, pose errors included, and averaging over stations lowers the pose
  part only as far as the stations are independent. An observation further
  than `gateW` standard deviations from the prediction, or whose
  normalised residual in the adjustment exceeds it, is not used; a vertex
  whose own pair is contradicted by two or more such observations is a
  wrong conjugate and left out. The along-line position stays the
  reference point's.
 ***************************************************************************/
#ifndef GEOSTATION_TRACING_MULTISTATIONVERTICES_H
#define GEOSTATION_TRACING_MULTISTATIONVERTICES_H

#include <string>
#include <vector>

#include "tracing/lineprofile.h"
#include "tracing/stereolinematcher.h"

namespace geostation
{

  //! A station's images of the line: the reference and partner cameras' images and their grey values.
  struct StationView
  {
    std::string stationId;
    std::vector<StereoImage> images; //!< pointers not owned
  };

  struct MultiStationOptions
  {
    double maxRangeM = 35.0;       //!< a station further from the vertex (horizontally) does not observe it
    double marginPx = 12.0;        //!< from the image border
    double minSearchHalfPx = 2.0;  //!< the line is looked for across it within 3 sigma of the prediction, at least this far
    double maxSearchHalfPx = 6.0;  //!< and at most this far
    double sigmaFloorPx = 0.15;    //!< across the line (the tracer raises it for painted stripes)
    double lineSigmaM = 0.0;       //!< the line's own sigma across it on the road (m), in each image's pixels at least (VertexMatchOptions::lineSigmaM)
    double gateW = 3.0;            //!< normalised offset or residual beyond which an observation is not used
    double minWidthPx = 1.5;       //!< a stripe narrower than this in another image is not located there
    double minCrossingSine = 0.1;  //!< locating in the partner: the line must cross the epipolar curve at least this steeply
    double onLineTolerancePx = 1.5; //!< locating in the partner: the reference point must be this close to the line in its own image
    /**
     * A vertex that lies in at least this many of the other stations'
     * images, where fewer than half of them find the line (within the
     * gate), while they confirm other vertices of its station, is not
     * confirmed and left out: a dash's ragged end, a worn patch, a wrong
     * conjugate. The line runs on between its confirmed neighbours. 0: kept.
     */
    int minLooksToConfirm = 2;
  };

  struct MultiStationSummary
  {
    int vertices = 0;        //!< refined with at least one other station's observation
    int observations = 0;    //!< other stations' observations used
    int rejected = 0;        //!< located but not used (gate or residual)
    int dropped = 0;         //!< vertices whose own pair the other stations contradict (left out)
    int unconfirmed = 0;     //!< vertices the other stations see but do not find the line at (left out, MultiStationOptions::minLooksToConfirm)
    double weightedSquares = 0.0; //!< sum of v^T Sigma^-1 v over the kept vertices' adjustments
    int redundancy = 0;           //!< their observations (rows) less 3 unknowns each
    //! A posteriori variance factor (sigma0 squared) of the adjustments; 1 without redundancy.
    double varianceFactor() const { return redundancy > 0 ? weightedSquares / redundancy : 1.0; }
  };

  /**
   * Vertices for reference points where the partner's followed line does
   * not reach (it stopped at worn paint, a dash ended): each point's ray
   * meets the road surface (`groundOfPixel`), the line is located across
   * that prediction in the partner (within the distance that
   * `heightToleranceM` above or below the surface makes along the epipolar
   * curve) and the ray is intersected with it. Points whose line is not
   * found, or that land further than the tolerance from the surface, are
   * left out.
   */
  std::vector<LineVertex3d> verticesByLocatingInPartner( const std::vector<Eigen::Vector2d> &referencePoints, const std::vector<double> &referenceSigmaPx,
      const StationView &own, const GroundOfPixel &groundOfPixel, const LineProfile &profile, double widthTimesRange, double heightToleranceM,
      const MultiStationOptions &options = MultiStationOptions() );

  /**
   * Adjusts `vertices` (of `own`, in the order followed; their 3-D tangent
   * is taken from their neighbours, or `lineDirection` for a lone vertex)
   * with the line located in `others`' images. `profile` is the line's in
   * the reference image, `widthTimesRange` a stripe's width in pixels times
   * its horizontal range in metres (0 for edges). Vertices keep their own
   * station's result when no other station sees them.
   */
  MultiStationSummary refineFromOtherStations( std::vector<LineVertex3d> &vertices, const StationView &own, const std::vector<StationView> &others,
      const LineProfile &profile, double widthTimesRange, const Eigen::Vector3d &lineDirection, const MultiStationOptions &options = MultiStationOptions() );

} // namespace geostation

#endif // GEOSTATION_TRACING_MULTISTATIONVERTICES_H

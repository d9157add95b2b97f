/***************************************************************************
  roadtracer.h - one click, the whole run traced (thesis §6.5)
  -------------------------------------------------------------------------
  traceRoadLine() follows a road line from an operator's seed through the
  stations of a mobile-mapping run: at each station the line is followed
  in the reference image (the seed's camera) up to the distance limit,
  found in the stereo partner (the station's other camera that sees it)
  and intersected into 3-D vertices with sigmas. Then the dynamic link
  (§6.5.3): the traced line - or, past its end, its straight continuation
  across a gap - is projected into the next station's reference image,
  where the first point at least handoverRangeM ahead of the camera is
  found on the line; tracing continues from there, and the previous
  station's vertices beyond that point are replaced by the nearer, more
  accurate ones. The result is one polyline for the run. The stations
  before see each vertex too (multistationvertices.h); the residuals there
  give the line's a posteriori sigma0, by which the finished line's sigmas
  are scaled.

  Expected failures are stop reasons with one sentence; whatever was traced
  before them is kept. Precondition violations (unknown or unoriented seed
  image) throw std::invalid_argument.
 ***************************************************************************/
#ifndef GEOSTATION_TRACING_ROADTRACER_H
#define GEOSTATION_TRACING_ROADTRACER_H

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "io/block.h"
#include "progress/progress.h"
#include "tracing/greyimagesource.h"
#include "tracing/lineprofile.h"
#include "tracing/handovermatcher.h"
#include "tracing/heightcontinuity.h"
#include "tracing/linefollower.h"
#include "tracing/linerelocation.h"
#include "tracing/multistationvertices.h"
#include "tracing/stereolinematcher.h"

namespace geostation
{

  struct TraceSeed
  {
    std::string id;
    std::string imageId;
    Eigen::Vector2d pixelInImage = Eigen::Vector2d::Zero();
    std::optional<double> directionDeg; //!< 0 = up the image, clockwise
  };

  struct TracedStation
  {
    std::string stationId, referenceImageId, partnerImageId;
    TraceMethod method = TraceMethod::Directional;
    LineKind kind = LineKind::BrightStripe;
    int pixelsFollowed = 0;
    int bridgedGaps = 0;
    int vertices = 0;         //!< kept in the run's line
    TraceStop stop = TraceStop::EndOfLine; //!< why following stopped in this station's reference image
    double partnerScore = 0.0;
    std::string partnerMessage; //!< why the line was not found in the partner (the station then has no vertices)
  };

  struct TracedVertex
  {
    Eigen::Vector3d point = Eigen::Vector3d::Zero();  //!< block CRS, metres
    Eigen::Vector3d sigmaM = Eigen::Vector3d::Zero();
    Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero(); //!< m^2
    std::string stationId;
    //! reference, partner, then the earlier stations' images that see the line there
    std::vector<std::string> imageIds;
    std::vector<Eigen::Vector2d> pixels;              //!< in those images (on the line, for the partner and the others)
    std::vector<Eigen::Vector2d> residualsPx;         //!< projected - observed (across the line, for the partner and the others)
    double rangeM = 0.0;                              //!< from the reference camera
  };

  struct RoadTraceOptions
  {
    TraceMethod method = TraceMethod::Auto;
    int maxStations = 0;           //!< 0: to the end of the run
    double maxRangeM = 20.0;       //!< distance limit: ground distance from the reference camera
    double handoverRangeM = 5.5;   //!< the next station takes the line over this far ahead of its camera
    double cameraHeightM = 2.6;    //!< above the road: the road plane of eqs. 6.22-6.25, following the track's heights
    double surfaceToleranceM = 0.3; //!< a vertex further above or below the road surface is a wrong match and dropped
    HeightContinuityOptions heightContinuity; //!< a vertex whose height leaves the line through its neighbours' is dropped
    double vertexSpacingPx = 25.0; //!< interval points matched in the partner
    int maxStationsPassedOver = 2; //!< stations in a row where the line cannot be followed before tracing stops
    /**
     * A painted stripe's centre is no better than this (px) in either image
     * when the points are used as followed (relocate false): worn paint and
     * its ragged edges move it together over many pixels, so the
     * per-profile sigma is too optimistic (measured on the simulator's
     * stripes with the exact orientation).
     */
    double stripeSigmaFloorPx = 0.5;
    /**
     * With relocate: a stripe's centre, located over a length of line, is
     * good to this (m) across the line on the road, in every image whatever
     * its range (VertexMatchOptions::lineSigmaM). Measured on the
     * simulator's worn stripes: normalised errors with a standard deviation
     * near 1 (0.7-1.0 on the highway run's lines with GNSS/INS errors).
     */
    double stripeSigmaM = 0.012;
    //! Vertices whose surroundings are looked for by correlation in the next station's image at the handover.
    int handoverCorrelations = 3;
    /**
     * Earlier stations whose images observe each vertex too (multi-station
     * intersection, refineFromOtherStations()); 0: the station's pair alone.
     */
    int stationsBehind = 2;
    /**
     * The previous station's vertices beyond the handover point give way to
     * this station's only where it has a vertex within this distance (m)
     * along the run; elsewhere (its partner line stopped short) they stay.
     */
    double giveWayM = 2.0;
    /**
     * The reference image's interval points and their conjugates in the
     * partner are put back onto the line, located on profiles averaged
     * over relocation.windowM of line on the ground (linerelocation.h);
     * false: as followed. The profile and width come from the seed.
     */
    bool relocate = true;
    LineRelocation relocation;
    //! Where the partner's followed line stops short, locate the line across each point's prediction in the partner.
    bool locateInPartner = true;
    //! A station whose start lies further than this (m) beyond the line so far follows the line back from its start too.
    double backfillGapM = 3.0;
    /**
     * The followed line is cut where it leaves the corridor of a road line
     * through its start, parallel to the van's track: this half width (m)
     * plus courseSlope times the distance along the track. Keeps a follower
     * or a bridge that went astray (a shadow's edge, a jump across the road
     * onto another line) out of the run; courseHalfWidthM 0 = no corridor.
     */
    double courseHalfWidthM = 0.6;
    double courseSlope = 0.08;
    /**
     * A station's vertex whose offset from the van's track leaves the
     * line's (the median over the 10 m before it) by more than this (m)
     * and 4 sigmas is dropped, and the rest of the station's part with the
     * second in a row (runline.h); 0 = not checked.
     */
    double maxLateralStepM = 0.12;
    /**
     * The finished line's sigmas scaled by the a posteriori variance factor
     * of its multi-station adjustments (the residuals in the stations
     * behind say how well the line was measured: a clean stripe better, a
     * worn or ragged one worse than the a priori stripe sigma), once their
     * redundancy reaches this; 0: a priori sigmas kept.
     */
    int minRedundancyToScaleSigma = 30;
    MultiStationOptions multiStation;
    HandoverOptions handover;
    LineFollowOptions follow;
    SeedOptions seed;
    StartMatchOptions start;
    VertexMatchOptions vertices;
    /**
     * Ground of a pixel instead of the road plane (e.g. a DEM through a
     * monoplotter); when unset, the road plane of the station's two cameras.
     */
    GroundOfPixel groundOfPixel;
    /**
     * Called after each station with what was followed there: the reference
     * and partner image lines in pixels, and the run's line so far (e.g. to
     * draw it live).
     */
    std::function<void( const TracedStation &, const std::vector<Eigen::Vector2d> &referenceLine, const std::vector<Eigen::Vector2d> &partnerLine,
                        const std::vector<TracedVertex> &lineSoFar )> stationTraced;
    //! Told after each station the fraction of the run done ("station ID") and asked whether to stop: a stop ends the trace with TraceStop::Cancelled.
    Progress progress;

    //! Throws std::invalid_argument naming the first bad value.
    void check() const;
  };


  struct RoadTraceSummary
  {
    std::vector<TracedVertex> vertices;
    std::vector<TracedStation> stations;
    TraceStop stop = TraceStop::EndOfLine;
    std::string message;      //!< one sentence: why tracing stopped
    double lengthM = 0.0;
    double sigmaMaxM = 0.0;   //!< largest vertex sigma (any axis)
    int pixelsFollowed = 0;
    MultiStationSummary multiStation; //!< vertices seen from earlier stations too
    int heightOutliers = 0;   //!< vertices dropped for leaving the line's height (heightcontinuity.h)
    int lateralOutliers = 0;  //!< vertices dropped for leaving the line's course sideways (runline.h)
    int stationsPassedOver = 0; //!< stations the dynamic link passed over (the line not found in their images)
    double sigma0 = 1.0;      //!< a posteriori sigma0 of the multi-station adjustments
    bool sigmaScaled = false; //!< the vertices' sigmas scaled by sigma0 squared (RoadTraceOptions::minRedundancyToScaleSigma)

    bool ok() const { return vertices.size() >= 2; }
    //! The methods used, "directional" or e.g. "least_squares+polynomial".
    std::string methods() const;
  };

  /**
   * Traces one line from a seed through the run; see the file comment.
   * Throws std::invalid_argument for an unknown or unoriented seed image or
   * bad options.
   */
  RoadTraceSummary traceRoadLine( const Block &block, const TraceSeed &seed, const RoadTraceOptions &options, const GreyImageSource &images );

} // namespace geostation

#endif // GEOSTATION_TRACING_ROADTRACER_H

/***************************************************************************
  stationstereo.h - one station's reference line found in the partner, in 3-D
  -------------------------------------------------------------------------
  The stereo step of road tracing at one station (thesis §6.5.1-6.5.2),
  taken out of traceRoadLine(): interval points along the reference line
  (put back onto the line, linerelocation.h); the start in the partner by
  correlation along the epipolar curve, tried at the first points the
  partner sees; the partner's line followed both ways from there with the
  reference's method; each point's conjugate where its epipolar curve
  crosses that line, intersected; where the partner's line stops short, the
  line located across the prediction (verticesByLocatingInPartner()); and
  every vertex observed again in the images of the stations traced before
  (refineFromOtherStations()).
 ***************************************************************************/
#ifndef GEOSTATION_TRACING_STATIONSTEREO_H
#define GEOSTATION_TRACING_STATIONSTEREO_H

#include <functional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "geometry/windowshape.h"
#include "tracing/linefollower.h"
#include "tracing/multistationvertices.h"
#include "tracing/stereolinematcher.h"

namespace geostation
{
  struct RoadTraceOptions;

  //! What the tracer knows of a station when its reference line has been followed.
  struct StationStereoInput
  {
    std::string stationId;
    StereoImage reference, partner;
    GroundOfPixel ground;                  //!< the road surface under a pixel of either image
    FollowResult referenceLine;            //!< followed in the reference image
    FollowRequest request;                 //!< how it was followed (profile, limit); the partner's start and direction replace its own
    TraceMethod method = TraceMethod::Polynomial; //!< the method that followed it, used in the partner too
    LineFollowOptions follow;              //!< as for the reference; the partner's ground distance replaces its own
    std::function<bool( const Eigen::Vector2d & )> partnerWithinLimit; //!< the distance limit in the partner
    LineProfile profile;                   //!< the line at this station (its width at the start's range)
    double widthTimesRange = 0.0;          //!< stripes: width (px) x range (m); 0 for edges
    Eigen::Vector3d lineDirection = Eigen::Vector3d::Zero(); //!< on the ground, the way tracing goes (zero: not known yet)
    std::vector<StationView> behind;       //!< the stations traced before, nearest first
  };

  struct StationStereo
  {
    StartMatch partnerStart;               //!< ok false: message says why the line is not in the partner
    LineFollowResult partnerLine;
    std::vector<LineVertex3d> vertices;    //!< in the reference line's order
    MultiStationSummary multiStation;
  };

  //! The station's vertices from its reference line (see the file comment). Expected failures leave vertices empty.
  StationStereo traceStationStereo( const StationStereoInput &input, const RoadTraceOptions &options );

} // namespace geostation

#endif // GEOSTATION_TRACING_STATIONSTEREO_H

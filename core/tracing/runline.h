/***************************************************************************
  runline.h - one station's vertices into the run's traced line
  -------------------------------------------------------------------------
  The tracer builds one line for the whole run, station by station. Each
  station's 3-D vertices join it here:
  - the previous station's vertices beyond the handover point give way,
    but only where this station has vertices of its own (within
    `giveWayM` along the run): where this station's line stopped short,
    they fill its gap;
  - a vertex far above or below the road surface (`surfaceToleranceM`,
    when a surface is known) is a wrong conjugate and left out, and so is
    one behind the line's end;
  - the station's vertices go in order along the run;
  - a vertex whose height leaves the line through its neighbours' is
    dropped (heightcontinuity.h);
  - road lines run with the road: with the van's track given, a vertex
    whose offset from the track leaves the line's over the last 10 m
    before it by more than maxLateralStepM and 4 sigmas is dropped, and
    at the second such vertex in a row the rest of the station's part
    goes too (the follower slid onto a parallel edge: the paint beside a
    kerb face, a shadow's edge).
 ***************************************************************************/
#ifndef GEOSTATION_TRACING_RUNLINE_H
#define GEOSTATION_TRACING_RUNLINE_H

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "tracing/roadtracer.h"

namespace geostation
{

  //! The station whose vertices join, and how.
  struct StationPart
  {
    std::string stationId, referenceImageId, partnerImageId;
    Eigen::Vector3d runAlong = Eigen::Vector3d::UnitX(); //!< the run's direction at this station (block CRS)
    size_t keep = 0;                                     //!< the line's vertices before the handover point
    //! The road surface's height under a point (m), or nothing where unknown (no surface test).
    std::function<std::optional<double>( const Eigen::Vector3d & )> surfaceHeight;
    //! The reference camera's path through the run (block CRS), for the lateral check; none: not checked.
    const std::vector<Eigen::Vector3d> *trajectory = nullptr;
  };

  struct StationPartSummary
  {
    size_t firstOfStation = 0; //!< index of the station's first vertex in the line
    int ownVertices = 0;       //!< this station's vertices kept (not counting the previous station's that stayed)
    int heightOutliers = 0;    //!< vertices dropped for leaving the line's height
    int lateralOutliers = 0;   //!< vertices dropped for leaving the line's course sideways
  };

  /**
   * Appends `vertices` (one station's, in any order) to `line`; see the
   * file comment. `options` gives giveWayM, surfaceToleranceM and
   * heightContinuity.
   */
  StationPartSummary appendStationPart( std::vector<TracedVertex> &line, const std::vector<LineVertex3d> &vertices, const StationPart &part, const RoadTraceOptions &options );

} // namespace geostation

#endif // GEOSTATION_TRACING_RUNLINE_H

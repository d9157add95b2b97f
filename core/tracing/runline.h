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
    dropped (heightcontinuity.h).
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
  };

  struct StationPartSummary
  {
    size_t firstOfStation = 0; //!< index of the station's first vertex in the line
    int ownVertices = 0;       //!< this station's vertices kept (not counting the previous station's that stayed)
    int heightOutliers = 0;    //!< vertices dropped for leaving the line's height
  };

  /**
   * Appends `vertices` (one station's, in any order) to `line`; see the
   * file comment. `options` gives giveWayM, surfaceToleranceM and
   * heightContinuity.
   */
  StationPartSummary appendStationPart( std::vector<TracedVertex> &line, const std::vector<LineVertex3d> &vertices, const StationPart &part, const RoadTraceOptions &options );

} // namespace geostation

#endif // GEOSTATION_TRACING_RUNLINE_H

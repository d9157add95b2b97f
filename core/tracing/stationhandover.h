/***************************************************************************
  stationhandover.h - the traced line handed over to the next station
  -------------------------------------------------------------------------
  Internal to tracing (RoadTraceRun calls it once per station). Which
  station comes next: before the first handover, the neighbour in time
  that lies ahead along the line; after it, the next one the same way
  through the run. The next station must lie ahead of this one along the
  way the run has gone, or the run's stations are out of order. The line
  is looked for in its image by the dynamic link (dynamiclink.h); where it
  is not found there (a car or a shadow's edge hides it), the stations
  after it are tried, as many as the options let be passed over.
 ***************************************************************************/
#ifndef GEOSTATION_TRACING_STATIONHANDOVER_H
#define GEOSTATION_TRACING_STATIONHANDOVER_H

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "tracing/dynamiclink.h"
#include "tracing/greyimagesource.h"
#include "tracing/roadtracer.h"
#include "tracing/runtrack.h"

namespace geostation
{

  //! This station's line and where the run stands.
  struct HandoverInput
  {
    const Block *block = nullptr;
    const RunTrack *track = nullptr;
    const GreyImageSource *images = nullptr;
    std::string seedImageId;                  //!< (messages: the image whose part the reference plays)
    int station = 0;                          //!< this station, an index into track->sequence()
    int step = 0;                             //!< +1 or -1 through the run; 0 before the first handover
    const OrientedImage *reference = nullptr; //!< this station's reference image
    const cv::Mat *referenceGrey = nullptr;
    std::optional<Eigen::Vector3d> previousCentre; //!< the last station's reference camera, none at the first
    const FollowResult *followed = nullptr;   //!< the line followed in the reference image (its stop says why, when it goes no further)
    const std::vector<TracedVertex> *vertices = nullptr; //!< the run's line so far
    size_t firstOfStation = 0;                //!< this station's first vertex in it
    const std::vector<Eigen::Vector3d> *groundLine = nullptr; //!< the line on the ground so far
    Eigen::Vector3d lineDirection = Eigen::Vector3d::Zero();  //!< over its last 20 m
    LineProfile profile;
    double widthTimesRange = 0.0;             //!< a stripe's width (px) times its range (m); 0 for edges
  };

  //! Where the line goes on, or why it does not.
  struct Handover
  {
    std::optional<TraceStop> stop;            //!< set when the line goes no further
    std::string message;                      //!< one sentence with the stop
    int station = 0;                          //!< the next station, an index into the sequence
    int step = 0;                             //!< +1 or -1 through the run
    int passedOver = 0;                       //!< stations between this one and the next where the line was not found
    DynamicLink link;                         //!< the start and direction in the next station's image, the vertices kept
    std::shared_ptr<const cv::Mat> grey;      //!< the next station's reference image

    bool ok() const { return !stop; }
  };

  //! The line's start in the next station ahead along it (thesis §6.5.3), or the stop.
  Handover handOverToNextStation( const HandoverInput &in, const RoadTraceOptions &options );

} // namespace geostation

#endif // GEOSTATION_TRACING_STATIONHANDOVER_H

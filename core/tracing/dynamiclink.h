/***************************************************************************
  dynamiclink.h - from one station to the next (thesis §6.5.3)
  -------------------------------------------------------------------------
  Where a traced line goes on in the next station's image. Candidates are
  this station's vertices, then the line's continuation along the van's
  track and straight on (across a gap, past a station where following
  failed). The first candidate at least handoverRangeM ahead of the next
  camera that is found on the line there becomes the new start; the run's
  vertices up to it are kept.

  When the two stations' GNSS/INS sigmas let them disagree by more than
  the 8 px the line is looked for in, a vertex about 10 m ahead is first
  found in the next image by correlation (refineHandover), and every
  candidate moves by the disagreement on the ground that this reveals.
 ***************************************************************************/
#ifndef GEOSTATION_TRACING_DYNAMICLINK_H
#define GEOSTATION_TRACING_DYNAMICLINK_H

#include <optional>
#include <vector>

#include "tracing/roadtracer.h"

namespace geostation
{

  struct DynamicLinkInput
  {
    const OrientedImage *reference = nullptr; //!< this station's reference image
    const cv::Mat *referenceGrey = nullptr;
    const OrientedImage *next = nullptr;      //!< the next station's image of the same camera
    const cv::Mat *nextGrey = nullptr;
    GroundOfPixel nextGround;                 //!< the road surface as the next station sees it
    const std::vector<TracedVertex> *vertices = nullptr; //!< the run's line so far
    size_t firstOfStation = 0;                //!< this station's first vertex in it
    const std::vector<Eigen::Vector3d> *groundLine = nullptr; //!< the line on the ground so far (vertices, or the followed line on the road)
    Eigen::Vector3d lineDirection = Eigen::Vector3d::Zero(); //!< over its last 20 m
    const std::vector<Eigen::Vector3d> *trajectory = nullptr; //!< the reference camera's path, in run order
    int step = 1;                             //!< +1 or -1 through the run
    LineProfile profile;
    double widthTimesRange = 0.0;             //!< a stripe's width (px) times its range (m); 0 for edges
  };

  struct DynamicLink
  {
    Eigen::Vector2d start = Eigen::Vector2d::Zero(); //!< on the line in the next image
    Eigen::Vector2d direction = Eigen::Vector2d::Zero();
    size_t keep = 0;                                 //!< the run's vertices kept before the next station's
  };

  //! The start in the next station's image, or nothing when the line is not found there.
  std::optional<DynamicLink> linkToNextStation( const DynamicLinkInput &in, const RoadTraceOptions &options );

} // namespace geostation

#endif // GEOSTATION_TRACING_DYNAMICLINK_H

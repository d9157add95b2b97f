/***************************************************************************
  viewcone.h - what a camera sees, drawn on the map
  -------------------------------------------------------------------------
  The Overview shows each camera of the current station as a polygon on
  the map: the projection centre and where the rays of the frame border
  meet the ground (a horizontal plane at the ground height under the
  camera), or, for rays that do not meet it within the range, the point at
  that horizontal range along them. The convex hull of these points is the
  cone: a wedge for a van's forward camera, the footprint for a nadir photo.
 ***************************************************************************/
#ifndef GEOSTATION_WORKSTATION_VIEWCONE_H
#define GEOSTATION_WORKSTATION_VIEWCONE_H

#include <vector>

#include <Eigen/Core>

#include "geometry/projection.h"

namespace geostation
{

  struct ViewConeOptions
  {
    double groundHeightM = 0.0;  //!< Z of the ground plane (block CRS)
    double maxRangeM = 40.0;     //!< horizontal distance from the projection centre
    int samplesPerSide = 8;      //!< border pixels per frame side
  };

  /**
   * The cone as a counter-clockwise ring of map points (XY, block CRS, not
   * closed). Empty if no border ray is defined. Throws std::invalid_argument
   * for a non-positive range or fewer than 1 sample per side.
   */
  std::vector<Eigen::Vector2d> viewCone( const OrientedImage &image, const ViewConeOptions &options = ViewConeOptions() );

  //! Convex hull (Andrew's monotone chain), counter-clockwise, not closed.
  std::vector<Eigen::Vector2d> convexHull( std::vector<Eigen::Vector2d> points );

} // namespace geostation

#endif // GEOSTATION_WORKSTATION_VIEWCONE_H

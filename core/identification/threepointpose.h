/***************************************************************************
  threepointpose.h - a camera's pose from three rays (P3P)
  -------------------------------------------------------------------------
  The exterior orientation of a calibrated camera from three ground points
  and their rays (ideal normalised coordinates, docs/conventions.md §2-3: y up, the
  camera looking along -z): up to four solutions, by OpenCV's AP3P. Used to
  turn a hypothesis of three correspondences into a pose that predicts
  every other control point.
 ***************************************************************************/
#ifndef GEOSTATION_IDENTIFICATION_THREEPOINTPOSE_H
#define GEOSTATION_IDENTIFICATION_THREEPOINTPOSE_H

#include <array>
#include <vector>

#include <Eigen/Core>

namespace geostation
{

  struct ThreePointPose
  {
    Eigen::Matrix3d cameraFromWorld = Eigen::Matrix3d::Identity(); //!< R^T of docs/conventions.md §3
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();              //!< projection centre, the ground points' frame
  };

  /**
   * The poses (0-4) that put all three points in front of the camera on
   * their rays. `ideal` are x, y of rays (x, y, -1) in the camera frame.
   */
  std::vector<ThreePointPose> threePointPoses( const std::array<Eigen::Vector3d, 3> &world, const std::array<Eigen::Vector2d, 3> &ideal );

} // namespace geostation

#endif // GEOSTATION_IDENTIFICATION_THREEPOINTPOSE_H

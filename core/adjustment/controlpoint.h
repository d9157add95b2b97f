/***************************************************************************
  controlpoint.h - ground control and its measurements in an image
  -------------------------------------------------------------------------
  A control point's known coordinates (block CRS, metres) with their
  sigmas, and a control point measured in an image: the inputs of space
  resection and of the bundle adjustment (CONVENTIONS §6 tables).
 ***************************************************************************/
#ifndef GEOSTATION_ADJUSTMENT_CONTROLPOINT_H
#define GEOSTATION_ADJUSTMENT_CONTROLPOINT_H

#include <string>

#include <Eigen/Core>

namespace geostation
{

  //! A ground point with known coordinates (block CRS, metres).
  struct ControlPoint
  {
    std::string id;
    Eigen::Vector3d world = Eigen::Vector3d::Zero();
    Eigen::Vector3d sigmaM = Eigen::Vector3d::Zero(); //!< 0: held fixed
    bool check = false; //!< a check point: not used in the adjustment, only evaluated
  };

  //! A control point measured in the image.
  struct ImagePoint
  {
    std::string pointId;
    Eigen::Vector2d pixelInImage = Eigen::Vector2d::Zero();
    double sigmaPx = 0.5;
  };

} // namespace geostation

#endif // GEOSTATION_ADJUSTMENT_CONTROLPOINT_H

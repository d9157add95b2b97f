/***************************************************************************
  controlpoint.h - ground control and its measurements in an image
  -------------------------------------------------------------------------
  A control point's known coordinates (block CRS, metres) with their
  sigmas, and a control point measured in an image: the inputs of space
  resection and of the bundle adjustment (docs/conventions.md §6 tables).
 ***************************************************************************/
#ifndef GEOSTATION_ADJUSTMENT_CONTROLPOINT_H
#define GEOSTATION_ADJUSTMENT_CONTROLPOINT_H

#include <cmath>
#include <cstdio>
#include <stdexcept>
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

  /**
   * The largest coordinate (m) a point on or near the Earth has in a
   * projected or local engineering CRS: the equator is 40 000 km long, so
   * 100 000 km leaves room for any false easting or northing.
   */
  constexpr double kMaxPlausibleCoordinateM = 1e8;

  //! Throws std::invalid_argument naming the point when a coordinate is not a number or lies beyond any plausible position.
  inline void checkPlausiblePosition( const ControlPoint &point )
  {
    const Eigen::Vector3d &p = point.world;
    if ( std::abs( p.x() ) <= kMaxPlausibleCoordinateM && std::abs( p.y() ) <= kMaxPlausibleCoordinateM && std::abs( p.z() ) <= kMaxPlausibleCoordinateM )
      return;
    char text[160];
    std::snprintf( text, sizeof text, "(X %.6g, Y %.6g, Z %.6g m)", p.x(), p.y(), p.z() );
    throw std::invalid_argument( "control point '" + point.id + "' lies beyond any plausible position " + text + ": coordinates in a projected CRS stay within 100 000 km" );
  }

  //! A control point measured in the image.
  struct ImagePoint
  {
    std::string pointId;
    Eigen::Vector2d pixelInImage = Eigen::Vector2d::Zero();
    double sigmaPx = 0.5;
  };

} // namespace geostation

#endif // GEOSTATION_ADJUSTMENT_CONTROLPOINT_H

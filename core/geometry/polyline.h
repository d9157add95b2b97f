/***************************************************************************
  polyline.h - lengths along a polyline of object-space points
 ***************************************************************************/
#ifndef GEOSTATION_GEOMETRY_POLYLINE_H
#define GEOSTATION_GEOMETRY_POLYLINE_H

#include <cstddef>
#include <vector>

#include <Eigen/Core>

namespace geostation
{

  //! The plan length (XY) of a polyline from its vertex `from` to its end; 0 for fewer than two vertices.
  inline double polylineLengthXY( const std::vector<Eigen::Vector3d> &points, size_t from = 0 )
  {
    double length = 0.0;
    for ( size_t i = from + 1; i < points.size(); ++i )
      length += ( points[i] - points[i - 1] ).head<2>().norm();
    return length;
  }

} // namespace geostation

#endif // GEOSTATION_GEOMETRY_POLYLINE_H

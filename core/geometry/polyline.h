/***************************************************************************
  polyline.h - lengths along a polyline of object-space points, and the
  nearest point of an image-space polyline
 ***************************************************************************/
#ifndef GEOSTATION_GEOMETRY_POLYLINE_H
#define GEOSTATION_GEOMETRY_POLYLINE_H

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
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

  //! The nearest point of a polyline: its distance and the unit direction of the segment it lies on (zero on a single point).
  struct PolylineNearest
  {
    double distance = std::numeric_limits<double>::infinity(); //!< infinity for no vertices
    Eigen::Vector2d direction = Eigen::Vector2d::Zero();
  };

  //! The point of the 2-D polyline `line` nearest `q` (a repeated vertex is a point, without a direction).
  inline PolylineNearest nearestOnPolyline( const std::vector<Eigen::Vector2d> &line, const Eigen::Vector2d &q )
  {
    PolylineNearest best;
    if ( line.size() == 1 )
      best.distance = ( line[0] - q ).norm();
    for ( size_t k = 0; k + 1 < line.size(); ++k )
    {
      const Eigen::Vector2d ab = line[k + 1] - line[k];
      const double squared = ab.squaredNorm();
      const double t = squared > 0.0 ? std::clamp( ( q - line[k] ).dot( ab ) / squared, 0.0, 1.0 ) : 0.0;
      const double d = ( line[k] + t * ab - q ).norm();
      if ( d < best.distance )
        best = { d, squared > 0.0 ? Eigen::Vector2d( ab / std::sqrt( squared ) ) : Eigen::Vector2d::Zero() };
    }
    return best;
  }

} // namespace geostation

#endif // GEOSTATION_GEOMETRY_POLYLINE_H

/***************************************************************************
  polyline.h - lengths along a polyline of object-space points, and the
  nearest point of a polyline (in image or object space, or in plan)
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

  /**
   * The nearest point of a polyline: its distance, where it lies (segment
   * k joins vertices k and k + 1; t from 0 at vertex k to 1 at k + 1) and
   * the unit direction of that segment (zero on a single point or a
   * repeated vertex). `Point`: Eigen::Vector2d or Eigen::Vector3d.
   */
  template <typename Point> struct NearestOnPolyline
  {
    double distance = std::numeric_limits<double>::infinity(); //!< infinity for no vertices
    size_t segment = 0;
    double t = 0.0;
    Point direction = Point::Zero();
  };
  using PolylineNearest = NearestOnPolyline<Eigen::Vector2d>;

  //! Where on the segment a-b the point nearest q lies: 0 at a, 1 at b (0 for a segment of no length).
  template <typename Point> double nearestOnSegment( const Point &a, const Point &b, const Point &q )
  {
    const Point ab = b - a;
    const double squared = ab.squaredNorm();
    return squared > 0.0 ? std::clamp( ( q - a ).dot( ab ) / squared, 0.0, 1.0 ) : 0.0;
  }

  //! The distance from q to the segment a-b.
  template <typename Point> double distanceToSegment( const Point &q, const Point &a, const Point &b )
  {
    return ( a + nearestOnSegment( a, b, q ) * ( b - a ) - q ).norm();
  }

  namespace detail
  {
    //! nearestOnPolyline over the points `at(k)` of a polyline of n vertices.
    template <typename Point, typename At> NearestOnPolyline<Point> nearestOf( size_t n, const At &at, const Point &q )
    {
      NearestOnPolyline<Point> best;
      if ( n == 1 )
        best.distance = ( at( 0 ) - q ).norm();
      for ( size_t k = 0; k + 1 < n; ++k )
      {
        const Point a = at( k ), ab = at( k + 1 ) - a;
        const double t = nearestOnSegment( a, Point( a + ab ), q );
        const double d = ( a + t * ab - q ).norm();
        if ( d < best.distance )
        {
          best.distance = d;
          best.segment = k;
          best.t = t;
          best.direction = ab.squaredNorm() > 0.0 ? Point( ab.normalized() ) : Point( Point::Zero() );
        }
      }
      return best;
    }
  } // namespace detail

  //! The point of the polyline `line` nearest `q` (a repeated vertex is a point, without a direction).
  template <typename Point> NearestOnPolyline<Point> nearestOnPolyline( const std::vector<Point> &line, const Point &q )
  {
    return detail::nearestOf<Point>( line.size(), [&]( size_t k ) { return line[k]; }, q );
  }

  //! The same in plan: the point of an object-space polyline nearest `q` in XY.
  inline NearestOnPolyline<Eigen::Vector2d> nearestOnPolylineXY( const std::vector<Eigen::Vector3d> &line, const Eigen::Vector2d &q )
  {
    return detail::nearestOf<Eigen::Vector2d>( line.size(), [&]( size_t k ) { return Eigen::Vector2d( line[k].head<2>() ); }, q );
  }

} // namespace geostation

#endif // GEOSTATION_GEOMETRY_POLYLINE_H

/***************************************************************************
  trackgeometry.cpp
 ***************************************************************************/
#include "tracing/trackgeometry.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Dense>

#include "geometry/polyline.h"

namespace geostation
{

  std::vector<Eigen::Vector3d> continuation( const std::vector<Eigen::Vector3d> &vertices, const Eigen::Vector3d &direction, double length, double step )
  {
    const Eigen::Vector3d end = vertices.back();
    size_t first = vertices.size() - 1;
    while ( first > 0 && ( end - vertices[first - 1] ).head<2>().norm() < 30.0 )
      --first;
    Eigen::Vector2d axis = direction.head<2>().normalized();
    double slope = 0.0, bend = 0.0, grade = direction.z() / std::max( 1e-9, direction.head<2>().norm() );
    const Eigen::Vector2d chord = end.head<2>() - vertices[first].head<2>();
    if ( vertices.size() - first >= 4 && chord.norm() > 6.0 )
    {
      // y = a + b x + c x^2 in a frame along the chord, origin at the end
      axis = chord.normalized();
      const Eigen::Vector2d normal( -axis.y(), axis.x() );
      Eigen::MatrixXd design( vertices.size() - first, 3 );
      Eigen::VectorXd across( design.rows() ), heights( design.rows() );
      for ( size_t i = first; i < vertices.size(); ++i )
      {
        const Eigen::Vector2d d = vertices[i].head<2>() - end.head<2>();
        const double x = d.dot( axis );
        design.row( i - first ) << 1.0, x, x * x;
        across[i - first] = d.dot( normal );
        heights[i - first] = vertices[i].z() - end.z();
      }
      const Eigen::Vector3d k = ( design.transpose() * design ).ldlt().solve( design.transpose() * across );
      slope = k[1];
      bend = std::clamp( k[2], -0.025, 0.025 ); // radius 20 m at the sharpest
      const Eigen::Vector2d g = design.leftCols<2>().colPivHouseholderQr().solve( heights );
      grade = g[1];
    }
    const Eigen::Vector2d normal( -axis.y(), axis.x() );
    std::vector<Eigen::Vector3d> out;
    for ( double s = step; s <= length + 1e-9; s += step )
    {
      // x along the chord; the curve's offset from it; arc length ~ x for gentle curves
      const double x = s;
      const Eigen::Vector2d xy = end.head<2>() + x * axis + ( slope * x + bend * x * x ) * normal;
      out.push_back( Eigen::Vector3d( xy.x(), xy.y(), end.z() + grade * x ) );
    }
    return out;
  }

  namespace
  {
    //! A place on the trajectory: the point (block CRS) and the direction of its leg (plan, unit).
    struct TrackPoint
    {
      Eigen::Vector3d point;
      Eigen::Vector2d legDirection;
    };

    /**
     * The trajectory at arc length `arcM` (plan metres from its first
     * point); the first and last legs extend straight on, legs of no
     * length are passed over.
     */
    TrackPoint trackPointAt( const std::vector<Eigen::Vector3d> &trajectory, double arcM )
    {
      TrackPoint out { trajectory.back(), Eigen::Vector2d::UnitX() };
      double arcSoFar = 0.0;
      bool firstLeg = true;
      for ( size_t i = 0; i + 1 < trajectory.size(); ++i )
      {
        const Eigen::Vector3d ab = trajectory[i + 1] - trajectory[i];
        const double length = ab.head<2>().norm();
        if ( length <= 0 )
          continue;
        out.legDirection = ab.head<2>() / length;
        if ( arcM <= arcSoFar + length || i + 2 == trajectory.size() )
        {
          const double along = firstLeg ? arcM - arcSoFar : std::max( arcM - arcSoFar, 0.0 );
          out.point = trajectory[i] + ( along / length ) * ab;
          return out;
        }
        firstLeg = false;
        arcSoFar += length;
      }
      return out;
    }
  }

  std::vector<Eigen::Vector3d> trajectoryContinuation( const std::vector<Eigen::Vector3d> &trajectory, const Eigen::Vector3d &last, int stepSign, double length, double step,
      std::optional<double> leftOffsetM )
  {
    std::vector<Eigen::Vector3d> out;
    if ( trajectory.size() < 2 )
      return out;
    const TrackCoordinates lastOnTrack = *trackCoordinates( trajectory, last.head<2>() );
    const double at = lastOnTrack.arcM, offset = leftOffsetM ? *leftOffsetM : lastOnTrack.leftOffsetM;
    const double z0 = trackPointAt( trajectory, at ).point.z();
    for ( double s = step; s <= length + 1e-9; s += step )
    {
      const TrackPoint p = trackPointAt( trajectory, at + stepSign * s );
      const Eigen::Vector2d xy = p.point.head<2>() + offset * Eigen::Vector2d( -p.legDirection.y(), p.legDirection.x() );
      out.push_back( Eigen::Vector3d( xy.x(), xy.y(), last.z() + ( p.point.z() - z0 ) ) );
    }
    return out;
  }

  std::optional<TrackCoordinates> trackCoordinates( const std::vector<Eigen::Vector3d> &trajectory, const Eigen::Vector2d &xy )
  {
    if ( trajectory.size() < 2 )
      return std::nullopt;
    double arcSoFar = 0.0, bestDistance = std::numeric_limits<double>::infinity();
    TrackCoordinates best;
    for ( size_t i = 0; i + 1 < trajectory.size(); ++i )
    {
      const Eigen::Vector2d a = trajectory[i].head<2>(), ab = trajectory[i + 1].head<2>() - a;
      const double len2 = ab.squaredNorm();
      const double legStart = arcSoFar;
      arcSoFar += std::sqrt( len2 );
      if ( len2 <= 0 )
        continue;
      const double t = ( xy - a ).dot( ab ) / len2; // unclamped at the ends: the trajectory extends straight
      if ( ( t < 0 && i > 0 ) || ( t > 1 && i + 2 < trajectory.size() ) )
        continue;
      const Eigen::Vector2d foot = a + t * ab;
      const double d = ( xy - foot ).norm();
      if ( d < bestDistance )
      {
        bestDistance = d;
        best.arcM = legStart + t * std::sqrt( len2 );
        const Eigen::Vector2d left( -ab.y(), ab.x() );
        best.leftOffsetM = ( xy - foot ).dot( left.normalized() );
      }
    }
    if ( !std::isfinite( bestDistance ) )
    {
      // a point in the wedge outside a bend, beyond every leg's ends: the nearest trajectory point
      size_t nearest = 0;
      for ( size_t i = 1; i < trajectory.size(); ++i )
        if ( ( trajectory[i].head<2>() - xy ).squaredNorm() < ( trajectory[nearest].head<2>() - xy ).squaredNorm() )
          nearest = i;
      double arcAt = 0.0;
      for ( size_t i = 1; i <= nearest; ++i )
        arcAt += ( trajectory[i] - trajectory[i - 1] ).head<2>().norm();
      const size_t i = std::min( nearest, trajectory.size() - 2 );
      const Eigen::Vector2d ab = ( trajectory[i + 1] - trajectory[i] ).head<2>();
      const Eigen::Vector2d left = Eigen::Vector2d( -ab.y(), ab.x() ).normalized();
      best.arcM = arcAt;
      best.leftOffsetM = ( xy - trajectory[nearest].head<2>() ).dot( left );
    }
    return best;
  }

  namespace
  {
    std::optional<Eigen::Vector2d> trackHeadingAt( const std::vector<Eigen::Vector3d> &trajectory, const Eigen::Vector3d &point )
    {
      const std::optional<TrackCoordinates> at = trackCoordinates( trajectory, point.head<2>() );
      if ( !at )
        return std::nullopt;
      const Eigen::Vector2d chord = ( trackPointAt( trajectory, at->arcM + 5.0 ).point - trackPointAt( trajectory, at->arcM - 5.0 ).point ).head<2>();
      if ( chord.norm() < 1e-6 )
        return std::nullopt;
      return Eigen::Vector2d( chord.normalized() );
    }
  }

  Eigen::Vector3d lineDirectionAt( const std::vector<Eigen::Vector3d> &trajectory, const Eigen::Vector3d &lineDirection, const Eigen::Vector3d &chordMiddle,
                                   const Eigen::Vector3d &point )
  {
    const std::optional<Eigen::Vector2d> from = trackHeadingAt( trajectory, chordMiddle ), to = trackHeadingAt( trajectory, point );
    if ( !from || !to )
      return lineDirection;
    const double turn = std::atan2( from->x() * to->y() - from->y() * to->x(), from->dot( *to ) );
    const double c = std::cos( turn ), s = std::sin( turn );
    return Eigen::Vector3d( c * lineDirection.x() - s * lineDirection.y(), s * lineDirection.x() + c * lineDirection.y(), lineDirection.z() ).normalized();
  }

  std::optional<double> recentTrackOffset( const std::vector<Eigen::Vector3d> &trajectory, const std::vector<Eigen::Vector3d> &line, double withinM, size_t minPoints )
  {
    if ( line.empty() || trajectory.size() < 2 )
      return std::nullopt;
    const double lastArc = trackCoordinates( trajectory, line.back().head<2>() )->arcM;
    std::vector<double> offsets;
    for ( const Eigen::Vector3d &p : line )
    {
      const TrackCoordinates c = *trackCoordinates( trajectory, p.head<2>() );
      if ( std::abs( c.arcM - lastArc ) <= withinM )
        offsets.push_back( c.leftOffsetM );
    }
    if ( offsets.size() < std::max<size_t>( minPoints, 1 ) )
      return std::nullopt;
    std::nth_element( offsets.begin(), offsets.begin() + offsets.size() / 2, offsets.end() );
    return offsets[offsets.size() / 2];
  }

  size_t pointsInCourse( const std::vector<Eigen::Vector3d> &trajectory, const Eigen::Vector3d &anchor, const std::vector<std::optional<Eigen::Vector3d>> &points,
                         double halfWidthM, double slope )
  {
    const std::optional<TrackCoordinates> origin = trackCoordinates( trajectory, anchor.head<2>() );
    if ( !origin )
      return points.size();
    for ( size_t i = 0; i < points.size(); ++i )
    {
      if ( !points[i] )
        continue;
      const TrackCoordinates c = *trackCoordinates( trajectory, points[i]->head<2>() );
      if ( std::abs( c.leftOffsetM - origin->leftOffsetM ) > halfWidthM + slope * std::abs( c.arcM - origin->arcM ) )
        return i;
    }
    return points.size();
  }

  std::optional<double> trackSurfaceHeight( const std::vector<Eigen::Vector3d> &trajectory, const Eigen::Vector2d &xy, double cameraHeightM )
  {
    if ( trajectory.empty() )
      return std::nullopt;
    if ( trajectory.size() == 1 )
      return trajectory.front().z() - cameraHeightM;
    const NearestOnPolyline<Eigen::Vector2d> n = nearestOnPolylineXY( trajectory, xy );
    const double z = trajectory[n.segment].z() + n.t * ( trajectory[n.segment + 1].z() - trajectory[n.segment].z() );
    return z - cameraHeightM;
  }

  std::vector<Eigen::Vector3d> smoothedHeights( const std::vector<Eigen::Vector3d> &trajectory, double halfWindowM )
  {
    std::vector<double> arc { 0.0 };
    for ( size_t i = 1; i < trajectory.size(); ++i )
      arc.push_back( arc.back() + ( trajectory[i] - trajectory[i - 1] ).head<2>().norm() );
    std::vector<Eigen::Vector3d> out = trajectory;
    for ( size_t i = 0; i < trajectory.size(); ++i )
    {
      std::vector<size_t> near;
      for ( size_t j = 0; j < trajectory.size(); ++j )
        if ( std::abs( arc[j] - arc[i] ) <= halfWindowM )
          near.push_back( j );
      const int terms = near.size() >= 5 ? 3 : near.size() >= 2 ? 2 : 1;
      Eigen::MatrixXd a( near.size(), terms );
      Eigen::VectorXd b( near.size() );
      for ( size_t r = 0; r < near.size(); ++r )
      {
        const double t = ( arc[near[r]] - arc[i] ) / std::max( halfWindowM, 1.0 );
        for ( int c = 0; c < terms; ++c )
          a( r, c ) = std::pow( t, c );
        b( r ) = trajectory[near[r]].z();
      }
      out[i].z() = a.colPivHouseholderQr().solve( b )( 0 );
    }
    return out;
  }

} // namespace geostation

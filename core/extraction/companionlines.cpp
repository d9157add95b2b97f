/***************************************************************************
  companionlines.cpp - markings, kerbs and shoulders are not roads
 ***************************************************************************/
#include "extraction/companionlines.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "extraction/verification.h"

namespace geostation
{

  namespace
  {
    double distanceToSegment( const Eigen::Vector2d &p, const Eigen::Vector2d &a, const Eigen::Vector2d &b )
    {
      const Eigen::Vector2d ab = b - a;
      const double t = ab.squaredNorm() > 0.0 ? std::clamp( ( p - a ).dot( ab ) / ab.squaredNorm(), 0.0, 1.0 ) : 0.0;
      return ( a + t * ab - p ).norm();
    }

    //! The distance from p to a polyline and the direction (unit) of the nearest segment.
    std::pair<double, Eigen::Vector2d> nearestOn( const Eigen::Vector2d &p, const std::vector<Eigen::Vector2d> &line )
    {
      double best = std::numeric_limits<double>::infinity();
      Eigen::Vector2d direction = Eigen::Vector2d::UnitX();
      for ( size_t i = 0; i + 1 < line.size(); ++i )
      {
        const double d = distanceToSegment( p, line[i], line[i + 1] );
        if ( d < best && ( line[i + 1] - line[i] ).norm() > 0.0 )
        {
          best = d;
          direction = ( line[i + 1] - line[i] ).normalized();
        }
      }
      return { best, direction };
    }

    /**
     * Whether `p` lies within `reachPx` of `other` and runs along it (within
     * 25 degrees): a road crossing a wider one near their junction lies
     * within reach but across it. `course` is the line's direction there.
     */
    bool alongside( const Eigen::Vector2d &p, const Eigen::Vector2d &course, const std::vector<Eigen::Vector2d> &other, double reachPx )
    {
      const double minCos = std::cos( 25.0 * 3.14159265358979323846 / 180.0 );
      const auto [distance, direction] = nearestOn( p, other );
      return distance <= reachPx && course.norm() > 0.0 && std::abs( course.normalized().dot( direction ) ) >= minCos;
    }
  } // namespace

  void CompanionLineOptions::check() const
  {
    if ( !( besideFraction > 0.0 && besideFraction <= 1.0 ) || !( narrowerBy > 0.0 && narrowerBy <= 1.0 ) || !( gapPx >= 0.0 ) )
      throw std::invalid_argument( "companion lines need a fraction of length and a width ratio in (0, 1] and a non-negative gap" );
  }

  CompanionLineSummary removeCompanionLines( const GreyTiles &grey, const std::vector<CompiledPolygon> &lines, const LineObjectOptions &object,
                                             const CompanionLineOptions &options )
  {
    options.check();
    std::vector<std::vector<Eigen::Vector2d>> dense;
    std::vector<double> widths;
    for ( const CompiledPolygon &line : lines )
    {
      dense.push_back( densifyPolyline( line.pixels, 4.0 ) );
      widths.push_back( measureBand( grey, dense.back(), object ).first );
    }
    CompanionLineSummary summary;
    for ( size_t q = 0; q < lines.size(); ++q )
    {
      // the share of the line's points alongside some wider line: a road broken into pieces (by a junction,
      // a tree's shadow) still has its shoulder beside it along its whole length
      const std::vector<Eigen::Vector2d> &points = dense[q];
      int beside = 0;
      for ( size_t i = 0; i < points.size(); ++i )
      {
        // the line's course over 6 points (24 px), not the jitter of a step
        const Eigen::Vector2d course = points[std::min( i + 3, points.size() - 1 )] - points[i > 3 ? i - 3 : 0];
        bool found = false;
        for ( size_t p = 0; p < lines.size() && !found; ++p )
          found = p != q && widths[q] <= options.narrowerBy * widths[p] && alongside( points[i], course, dense[p], 0.5 * ( widths[p] + widths[q] ) + options.gapPx );
        beside += found;
      }
      const bool companion = points.size() >= 2 && beside >= options.besideFraction * points.size();
      if ( companion )
      {
        ++summary.removed;
        continue;
      }
      summary.lines.push_back( lines[q] );
      summary.widthsPx.push_back( widths[q] );
    }
    return summary;
  }

} // namespace geostation

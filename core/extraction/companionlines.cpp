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
     * The share of `points` (a line densified) that lie within `reachPx` of
     * `other` and run along it (within 25 degrees): a road crossing a wider
     * one near their junction lies within reach but across it.
     */
    double shareAlongside( const std::vector<Eigen::Vector2d> &points, const std::vector<Eigen::Vector2d> &other, double reachPx )
    {
      if ( points.size() < 2 )
        return 0.0;
      const double minCos = std::cos( 25.0 * 3.14159265358979323846 / 180.0 );
      int alongside = 0;
      for ( size_t i = 0; i < points.size(); ++i )
      {
        // the line's course over 6 points (24 px), not the jitter of a step
        const Eigen::Vector2d here = points[std::min( i + 3, points.size() - 1 )] - points[i > 3 ? i - 3 : 0];
        const auto [distance, direction] = nearestOn( points[i], other );
        alongside += distance <= reachPx && here.norm() > 0.0 && std::abs( here.normalized().dot( direction ) ) >= minCos;
      }
      return static_cast<double>( alongside ) / points.size();
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
      bool companion = false;
      for ( size_t p = 0; p < lines.size() && !companion; ++p )
        companion = p != q && widths[q] <= options.narrowerBy * widths[p] &&
                    shareAlongside( dense[q], dense[p], 0.5 * ( widths[p] + widths[q] ) + options.gapPx ) >= options.besideFraction;
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

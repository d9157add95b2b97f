/***************************************************************************
  companionlines.cpp - markings, kerbs and shoulders are not roads
 ***************************************************************************/
#include "extraction/companionlines.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "extraction/verification.h"
#include "geometry/polyline.h"

namespace geostation
{

  namespace
  {
    constexpr double kStepPx = 4.0; //!< the lines are judged at points this far apart

    //! A line densified to kStepPx, with the band's width at each point and the length along it.
    struct DenseLine
    {
      std::vector<Eigen::Vector2d> points;
      std::vector<double> widths;
      std::vector<double> along;   //!< from the first point (pixels)
      std::vector<bool> vertex;    //!< a vertex of the line as compiled (not one added by densifying)
      double medianWidth = 0.0;
      Eigen::Vector2d low = Eigen::Vector2d::Constant( std::numeric_limits<double>::max() ), high = -low; //!< bounds of the points
    };

    double median( std::vector<double> v )
    {
      if ( v.empty() )
        return std::numeric_limits<double>::quiet_NaN();
      std::nth_element( v.begin(), v.begin() + v.size() / 2, v.end() );
      return v[v.size() / 2];
    }

    //! The line densified to kStepPx (its vertices kept), the length along it and its bounds; no widths yet.
    DenseLine densified( const CompiledPolygon &line )
    {
      DenseLine dense;
      for ( size_t i = 0; i < line.pixels.size(); ++i )
      {
        const std::vector<Eigen::Vector2d> segment =
          i == 0 ? std::vector<Eigen::Vector2d> { line.pixels[0] } : densifyPolyline( { line.pixels[i - 1], line.pixels[i] }, kStepPx );
        for ( size_t k = i == 0 ? 0 : 1; k < segment.size(); ++k )
        {
          dense.along.push_back( dense.points.empty() ? 0.0 : dense.along.back() + ( segment[k] - dense.points.back() ).norm() );
          dense.points.push_back( segment[k] );
          dense.vertex.push_back( k + 1 == segment.size() );
          dense.low = dense.low.cwiseMin( segment[k] );
          dense.high = dense.high.cwiseMax( segment[k] );
        }
      }
      dense.widths.assign( dense.points.size(), std::numeric_limits<double>::quiet_NaN() );
      return dense;
    }

    bool withinBounds( const Eigen::Vector2d &p, const DenseLine &line, double reachPx )
    {
      return p.x() >= line.low.x() - reachPx && p.y() >= line.low.y() - reachPx && p.x() <= line.high.x() + reachPx && p.y() <= line.high.y() + reachPx;
    }

    /**
     * The points of line q within `reachPx` of another line, or of itself
     * away from them along it: only there can it be a companion, or another
     * line's wider band. The rest of the network needs no widths.
     */
    std::vector<bool> pointsNearOthers( const std::vector<DenseLine> &lines, size_t q, double reachPx )
    {
      const DenseLine &line = lines[q];
      std::vector<bool> near( line.points.size(), false );
      for ( size_t i = 0; i < line.points.size(); ++i )
        for ( size_t p = 0; p < lines.size() && !near[i]; ++p )
        {
          const DenseLine &other = lines[p];
          if ( !withinBounds( line.points[i], other, reachPx ) )
            continue;
          for ( size_t k = 0; k + 1 < other.points.size() && !near[i]; ++k )
            near[i] = ( p != q || std::abs( other.along[k] - line.along[i] ) > reachPx + 2.0 * kStepPx ) &&
                      distanceToSegment( line.points[i], other.points[k], other.points[k + 1] ) <= reachPx;
        }
      return near;
    }

    /**
     * The band's width at the points of `near`: measured at every other one
     * (8 px apart) and taken as the median of the measurements within 16 px
     * along the line, so that one profile that took a marking or the
     * shoulder beside the band for it does not make the road narrow there
     * (a line compiled through a junction may run along a shoulder and then
     * along the road itself, so one width for the whole line would not do).
     * The line's median width: of those measurements, or measureBand()'s
     * where the line is near nothing; where no band is found nearby, the
     * median.
     */
    void measureWidths( const GreyTiles &grey, DenseLine &dense, const std::vector<bool> &near, const LineObjectOptions &object )
    {
      const size_t n = dense.points.size();
      std::vector<double> measured( n, std::numeric_limits<double>::quiet_NaN() ), all;
      for ( size_t i = 0; i < n && n >= 2; ++i )
      {
        if ( !near[i] || ( i % 2 == 1 && near[i - 1] ) )
          continue;
        const Eigen::Vector2d course = dense.points[std::min( i + 1, n - 1 )] - dense.points[i > 0 ? i - 1 : 0];
        if ( course.norm() == 0.0 )
          continue;
        if ( const std::optional<CrossSection> band = bandAt( grey, dense.points[i], course.normalized(), object ) )
          all.push_back( measured[i] = band->widthPx );
      }
      dense.medianWidth = !all.empty() ? median( all ) : measureBand( grey, dense.points, object ).first;
      for ( size_t i = 0; i < n; ++i )
      {
        std::vector<double> around;
        for ( size_t k = i > 4 ? i - 4 : 0; k < std::min( n, i + 5 ); ++k )
          if ( std::isfinite( measured[k] ) )
            around.push_back( measured[k] );
        dense.widths[i] = around.empty() ? dense.medianWidth : median( around );
      }
    }

    /**
     * Whether point i of `line` runs beside a wider band of `other` (which
     * may be the line itself, away from i along it): within half the two
     * widths and `gapPx`, along it within 25 degrees (a road crossing a
     * wider one near their junction lies within reach but across it), and
     * at most `narrowerBy` as wide.
     */
    bool besideWider( const DenseLine &line, size_t i, const DenseLine &other, bool self, const CompanionLineOptions &options )
    {
      const std::vector<Eigen::Vector2d> &points = line.points;
      // the line's course over 6 points (24 px), not the jitter of a step
      const Eigen::Vector2d course = points[std::min( i + 3, points.size() - 1 )] - points[i > 3 ? i - 3 : 0];
      if ( course.norm() == 0.0 )
        return false;
      const double minCos = std::cos( 25.0 * 3.14159265358979323846 / 180.0 );
      const double width = line.widths[i];
      for ( size_t k = 0; k + 1 < other.points.size(); ++k )
      {
        const double otherWidth = std::max( other.widths[k], other.widths[k + 1] );
        if ( width > options.narrowerBy * otherWidth )
          continue;
        const double reach = 0.5 * ( width + otherWidth ) + options.gapPx;
        // the line itself: only where it has come back beside itself (a shoulder and the road joined at a junction)
        if ( self && std::abs( other.along[k] - line.along[i] ) < 3.0 * reach + 2.0 * kStepPx )
          continue;
        const Eigen::Vector2d segment = other.points[k + 1] - other.points[k];
        if ( segment.norm() == 0.0 || distanceToSegment( points[i], other.points[k], other.points[k + 1] ) > reach )
          continue;
        if ( std::abs( course.normalized().dot( segment.normalized() ) ) >= minCos )
          return true;
      }
      return false;
    }

    //! Points i0..i1 of a dense line as a polyline: the compiled vertices between them and the two ends.
    std::vector<Eigen::Vector2d> piecePixels( const DenseLine &line, size_t i0, size_t i1 )
    {
      std::vector<Eigen::Vector2d> out;
      for ( size_t i = i0; i <= i1; ++i )
        if ( i == i0 || i == i1 || line.vertex[i] )
          out.push_back( line.points[i] );
      return out;
    }
  } // namespace

  void CompanionLineOptions::check() const
  {
    if ( !( besideFraction > 0.0 && besideFraction <= 1.0 ) || !( narrowerBy > 0.0 && narrowerBy <= 1.0 ) || !( gapPx >= 0.0 ) || !( narrowerThanRoads >= 0.0 ) )
      throw std::invalid_argument( "companion lines need a fraction of length and a width ratio in (0, 1], a non-negative gap and a non-negative fraction of the narrowest road" );
  }

  CompanionLineSummary removeCompanionLines( const GreyTiles &grey, const std::vector<CompiledPolygon> &lines, const LineObjectOptions &object,
                                             const CompanionLineOptions &options )
  {
    options.check();
    std::vector<DenseLine> dense;
    for ( const CompiledPolygon &line : lines )
      dense.push_back( densified( line ) );
    // the farthest a companion can lie from the band it runs beside
    const double reach = object.maxWidthPx + options.gapPx;
    for ( size_t q = 0; q < lines.size(); ++q )
      measureWidths( grey, dense[q], pointsNearOthers( dense, q, reach ), object );
    CompanionLineSummary summary;
    for ( size_t q = 0; q < lines.size(); ++q )
    {
      const DenseLine &line = dense[q];
      const size_t n = line.points.size();
      if ( n < 2 )
      {
        summary.lines.push_back( lines[q] );
        summary.widthsPx.push_back( line.medianWidth );
        continue;
      }
      // each point: alongside a wider band of another line, or of this one where it comes back beside itself (a
      // road found in pieces - by a junction, a tree's shadow - still has its shoulder beside it along its length)
      std::vector<bool> beside( n, false );
      for ( size_t i = 0; i < n; ++i )
        for ( size_t p = 0; p < lines.size() && !beside[i]; ++p )
          beside[i] = withinBounds( line.points[i], dense[p], reach ) && besideWider( line, i, dense[p], p == q, options );
      // a single point beside (8 px at most) is where a narrower road meets a wider one, not a companion
      const auto dropSinglePoints = [n]( std::vector<bool> &flags ) {
        for ( size_t i = 0; i < n; ++i )
          if ( flags[i] && ( i == 0 || !flags[i - 1] ) && ( i + 1 == n || !flags[i + 1] ) )
            flags[i] = false;
      };
      dropSinglePoints( beside );
      if ( std::count( beside.begin(), beside.end(), true ) >= options.besideFraction * n )
      {
        ++summary.removed;
        continue;
      }
      // in part a companion: the stretches beside a wider band and narrower than any road looked for (a shoulder
      // that the line ran along before a junction took it onto the road) go; each stretch left over is a line of
      // its own where it is long enough to be one (twice its width, at least 12 px)
      std::vector<bool> cut( n, false );
      for ( size_t i = 0; i < n; ++i )
        cut[i] = beside[i] && line.widths[i] < options.narrowerThanRoads * object.minWidthPx;
      dropSinglePoints( cut );
      if ( std::none_of( cut.begin(), cut.end(), []( bool c ) { return c; } ) )
      {
        summary.lines.push_back( lines[q] );
        summary.widthsPx.push_back( line.medianWidth );
        continue;
      }
      ++summary.cut;
      for ( size_t i = 0; i < n; )
      {
        if ( cut[i] )
        {
          ++i;
          continue;
        }
        size_t j = i;
        while ( j + 1 < n && !cut[j + 1] )
          ++j;
        const double width = median( std::vector<double>( line.widths.begin() + i, line.widths.begin() + j + 1 ) );
        if ( line.along[j] - line.along[i] >= std::max( 12.0, 2.0 * width ) )
        {
          CompiledPolygon piece = lines[q];
          piece.pixels = piecePixels( line, i, j );
          if ( i > 0 )
            piece.startEnd = PolygonEnd::DeadEnd;
          if ( j + 1 < n )
            piece.endEnd = PolygonEnd::DeadEnd;
          summary.lines.push_back( std::move( piece ) );
          summary.widthsPx.push_back( width );
        }
        i = j + 1;
      }
    }
    return summary;
  }

} // namespace geostation

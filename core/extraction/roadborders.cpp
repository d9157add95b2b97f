/***************************************************************************
  roadborders.cpp - a line along a road's border goes onto the road
 ***************************************************************************/
#include "extraction/roadborders.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>

#include "extraction/verification.h"
#include "geometry/polyline.h"
#include "imageproc/edgeprimitives.h"

namespace geostation
{

  void RoadBorderOptions::check() const
  {
    if ( !( stepPx >= 0.5 && stepPx <= 20.0 ) )
      throw std::invalid_argument( "the road borders' profile step must be 0.5-20 px" );
    if ( !( roadOverBorder >= 1.0 && roadOverBorder <= 10.0 ) )
      throw std::invalid_argument( "a road must be 1-10 times as wide as its border" );
    if ( !( touchingPx >= 0.0 && touchingPx <= 10.0 ) )
      throw std::invalid_argument( "the road borders' touching distance must be 0-10 px" );
    if ( !( minShare > 0.0 && minShare <= 1.0 ) || !( duplicateShare > 0.0 && duplicateShare <= 1.0 ) )
      throw std::invalid_argument( "the road borders' shares must be fractions in (0, 1]" );
    if ( smoothHalfWindow < 0 || !( toleranceDp > 0.0 && toleranceDp <= 2.0 ) )
      throw std::invalid_argument( "the road borders' smoothing window must be 0 or more and the simplification 0-2 px" );
  }

  namespace
  {
    //! A line's profiles: where, which way across, and the shift onto the road found there (px along `normal`).
    struct Profiles
    {
      std::vector<Eigen::Vector2d> at, normal;
      std::vector<std::optional<double>> shift;
      std::vector<double> roadWidth;
    };

    bool touching( const CrossSection &a, const CrossSection &b, double touchingPx )
    {
      return std::abs( a.offsetPx - b.offsetPx ) <= 0.5 * ( a.widthPx + b.widthPx ) + touchingPx;
    }

    /**
     * The road beside the line on one profile: a band `road` with a narrow
     * band touching it on the side away from the line (its far border, the
     * road at least roadOverBorder times as wide), the line not inside the
     * road but within a border's width of its edge, on the near border -
     * which need not show as a band of its own (a border merged with the
     * grass beside it is one wider band), but is not a band of the road's
     * own tone as wide as a road (that is a road beside a road). The
     * nearest such road, or nothing.
     */
    std::optional<CrossSection> roadBeside( const std::vector<CrossSection> &sections, double minRoadWidthPx, const RoadBorderOptions &options )
    {
      std::optional<CrossSection> best;
      for ( const CrossSection &road : sections )
      {
        const double fromEdge = std::abs( road.offsetPx ) - 0.5 * road.widthPx; // the line from the road's edge, outwards
        if ( fromEdge < -1.0 || road.widthPx < minRoadWidthPx )
          continue; // the line on the road (or on a marking in it), or too narrow a road
        const bool onARoad = std::any_of( sections.begin(), sections.end(), [&]( const CrossSection &c ) {
          return c.tone == road.tone && c.widthPx >= minRoadWidthPx && std::abs( c.offsetPx ) <= 0.5 * c.widthPx;
        } );
        if ( onARoad )
          continue;
        const double side = road.offsetPx < 0.0 ? 1.0 : -1.0; // the line's side of the road
        const bool farBorder = std::any_of( sections.begin(), sections.end(), [&]( const CrossSection &t ) {
          return ( t.offsetPx - road.offsetPx ) * side < 0.0 && std::abs( t.offsetPx - road.offsetPx ) >= 0.5 * road.widthPx &&
                 touching( t, road, options.touchingPx ) && road.widthPx >= options.roadOverBorder * t.widthPx &&
                 fromEdge <= t.widthPx + options.touchingPx;
        } );
        if ( farBorder && ( !best || std::abs( road.offsetPx ) < std::abs( best->offsetPx ) ) )
          best = road;
      }
      return best;
    }

    //! The line sampled every step with the road found beside it at each profile.
    Profiles roadsBeside( const GreyTiles &grey, const CompiledPolygon &line, const LineObjectOptions &object, const RoadBorderOptions &options )
    {
      Profiles p;
      p.at = densifyPolyline( line.pixels, options.stepPx );
      const size_t n = p.at.size();
      p.normal.assign( n, Eigen::Vector2d::Zero() );
      p.shift.assign( n, std::nullopt );
      p.roadWidth.assign( n, 0.0 );
      // a road as wide as the widest looked for, the line on its border and the twin beyond
      const int half = static_cast<int>( std::ceil( 1.5 * object.maxWidthPx ) ) + 8;
      for ( size_t i = 0; i < n; ++i )
      {
        const Eigen::Vector2d course = p.at[std::min( i + 2, n - 1 )] - p.at[i >= 2 ? i - 2 : 0];
        if ( course.norm() < 1e-6 )
          continue;
        const Eigen::Vector2d along = course.normalized();
        p.normal[i] = normalOf( along );
        const GreyWindow window = grey.around( p.at[i], half + 4 );
        if ( window.pixels.empty() )
          continue;
        const std::vector<double> profile = sampleCrossProfile( window.pixels, window.toWindow( p.at[i] ), along, half, object.polarity, 1.0, 3 );
        // borders may be narrower than any road looked for
        const std::vector<CrossSection> sections =
          findCrossSections( profile, 1.0, object.maxWidthPx, 0.5 * object.minContrast, 2.0 * object.maxVariation, false, object.polarity );
        if ( const std::optional<CrossSection> road = roadBeside( sections, object.minWidthPx, options ) )
        {
          p.shift[i] = road->offsetPx;
          p.roadWidth[i] = road->widthPx;
        }
      }
      return p;
    }

    double median( std::vector<double> v )
    {
      std::nth_element( v.begin(), v.begin() + v.size() / 2, v.end() );
      return v[v.size() / 2];
    }

    /**
     * Each profile's shift: the median of the shifts found within the
     * window on the road's side, where at least three were found there. A
     * gap of up to twice the window between such profiles (a car, a
     * junction) is bridged; across a longer one (the line leaves the
     * border: it runs on the road itself there, or folded back along it)
     * the shifts either side fade out over the window. Nothing when fewer
     * than minShare of the profiles show the road, or not on one side.
     */
    std::optional<std::vector<double>> smoothedShifts( const Profiles &p, const RoadBorderOptions &options )
    {
      const int n = static_cast<int>( p.at.size() );
      int left = 0, right = 0;
      for ( const std::optional<double> &s : p.shift )
        if ( s )
          ++( *s < 0.0 ? left : right );
      const double side = left > right ? -1.0 : 1.0;
      if ( std::max( left, right ) < options.minShare * n || n < 3 )
        return std::nullopt;
      const int window = options.smoothHalfWindow;
      std::vector<std::optional<double>> smooth( n );
      for ( int i = 0; i < n; ++i )
      {
        std::vector<double> near;
        for ( int k = std::max( 0, i - window ); k <= std::min( n - 1, i + window ); ++k )
          if ( p.shift[k] && *p.shift[k] * side > 0.0 )
            near.push_back( *p.shift[k] );
        if ( near.size() >= 3 || ( !near.empty() && static_cast<int>( near.size() ) * 2 >= std::min( n, 2 * window + 1 ) ) )
          smooth[i] = median( near );
      }
      std::vector<double> shifts( n, 0.0 );
      const int bridge = 2 * window + 1;
      const double fade = std::max( 1, window );
      for ( int i = 0; i < n; ++i )
      {
        if ( smooth[i] )
        {
          shifts[i] = *smooth[i];
          continue;
        }
        int before = i - 1, after = i + 1;
        while ( before >= 0 && !smooth[before] )
          --before;
        while ( after < n && !smooth[after] )
          ++after;
        const bool hasBefore = before >= 0, hasAfter = after < n;
        if ( hasBefore && hasAfter && after - before <= bridge )
          shifts[i] = *smooth[before] + double( i - before ) / ( after - before ) * ( *smooth[after] - *smooth[before] );
        else if ( ( !hasBefore || !hasAfter ) && ( hasBefore ? i - before : after - i ) <= window )
          shifts[i] = hasBefore ? *smooth[before] : *smooth[after]; // an end just past the last profile found
        else
          shifts[i] = ( hasBefore ? *smooth[before] * std::max( 0.0, 1.0 - ( i - before ) / fade ) : 0.0 ) +
                      ( hasAfter ? *smooth[after] * std::max( 0.0, 1.0 - ( after - i ) / fade ) : 0.0 );
      }
      return shifts;
    }

    //! The line's profiles moved by their shifts, the move growing from nothing over `rampPx` from an end at a junction.
    std::vector<Eigen::Vector2d> movedCourse( const Profiles &p, const std::vector<double> &shifts, const CompiledPolygon &line, double rampPx, double stepPx )
    {
      const int n = static_cast<int>( p.at.size() );
      std::vector<Eigen::Vector2d> moved( n );
      for ( int i = 0; i < n; ++i )
      {
        double weight = 1.0;
        if ( line.startEnd == PolygonEnd::Intersection )
          weight = std::min( weight, i * stepPx / rampPx );
        if ( line.endEnd == PolygonEnd::Intersection )
          weight = std::min( weight, ( n - 1 - i ) * stepPx / rampPx );
        // a profile without a course of its own (a line folded back on itself) takes its neighbour's
        Eigen::Vector2d normal = p.normal[i];
        for ( int k = 1; normal.norm() < 0.5 && k < n; ++k )
          normal = p.normal[std::clamp( i + ( k % 2 ? ( k + 1 ) / 2 : -k / 2 ), 0, n - 1 )];
        moved[i] = p.at[i] + std::clamp( weight, 0.0, 1.0 ) * shifts[i] * normal;
      }
      return moved;
    }

    //! For each point of `moved`: whether it runs within `reachPx` of one of the others' lines (their pieces), within 30 degrees of its direction.
    std::vector<bool> onOthers( const std::vector<Eigen::Vector2d> &moved, const std::vector<std::vector<CompiledPolygon>> &pieces, size_t self, double reachPx )
    {
      const double minCos = std::cos( 30.0 * M_PI / 180.0 );
      std::vector<bool> on( moved.size(), false );
      for ( size_t i = 0; i < moved.size(); ++i )
      {
        const Eigen::Vector2d course = moved[std::min( i + 2, moved.size() - 1 )] - moved[i >= 2 ? i - 2 : 0];
        if ( course.norm() < 1e-6 )
          continue;
        for ( size_t j = 0; j < pieces.size() && !on[i]; ++j )
          for ( const CompiledPolygon &other : pieces[j] )
          {
            const PolylineNearest n = j == self ? PolylineNearest() : nearestOnPolyline( other.pixels, moved[i] );
            if ( n.distance <= reachPx && std::abs( n.direction.dot( course.normalized() ) ) >= minCos )
            {
              on[i] = true;
              break;
            }
          }
      }
      return on;
    }

    //! The runs of `on` at least `minStretchPx` long (shorter ones are where a line meets another).
    std::vector<bool> longRuns( std::vector<bool> on, double stepPx, double minStretchPx )
    {
      for ( size_t i = 0; i < on.size(); )
      {
        size_t j = i;
        while ( j < on.size() && on[j] == on[i] )
          ++j;
        if ( on[i] && static_cast<double>( j - i ) * stepPx < minStretchPx )
          std::fill( on.begin() + static_cast<long>( i ), on.begin() + static_cast<long>( j ), false );
        i = j;
      }
      return on;
    }

    /**
     * The moved line without the stretches flagged `on` (running on
     * another line: the road found twice, both its shoulders followed, or
     * the road's own line there in part); the pieces left as long as
     * `minPiecePx` at least (or the whole line), a cut end a dead end.
     */
    std::vector<CompiledPolygon> withoutRepeats( const CompiledPolygon &line, const std::vector<Eigen::Vector2d> &moved, const std::vector<bool> &on, double stepPx,
                                                 double minPiecePx, double toleranceDp )
    {
      const size_t n = moved.size();
      std::vector<CompiledPolygon> pieces;
      for ( size_t i = 0; i < n; )
      {
        size_t j = i;
        while ( j < n && on[j] == on[i] )
          ++j;
        if ( !on[i] && ( j - 1 - i ) * stepPx >= std::min( minPiecePx, ( n - 1 ) * stepPx ) && j - i >= 2 )
        {
          CompiledPolygon piece = line;
          piece.pixels = douglasPeucker( std::vector<Eigen::Vector2d>( moved.begin() + static_cast<long>( i ), moved.begin() + static_cast<long>( j ) ), toleranceDp );
          if ( i > 0 )
            piece.startEnd = PolygonEnd::DeadEnd;
          else if ( line.startEnd == PolygonEnd::Intersection )
            piece.pixels.front() = line.pixels.front();
          if ( j < n )
            piece.endEnd = PolygonEnd::DeadEnd;
          else if ( line.endEnd == PolygonEnd::Intersection )
            piece.pixels.back() = line.pixels.back();
          pieces.push_back( std::move( piece ) );
        }
        i = j;
      }
      return pieces;
    }
  } // namespace

  RoadBorderSummary moveBordersOntoRoads( const GreyTiles &grey, const std::vector<CompiledPolygon> &lines, const LineObjectOptions &object,
                                          const RoadBorderOptions &options )
  {
    object.check();
    options.check();
    RoadBorderSummary summary;
    // each line as its pieces: itself where not moved
    std::vector<std::vector<CompiledPolygon>> pieces;
    for ( const CompiledPolygon &line : lines )
      pieces.push_back( { line } );
    for ( size_t l = 0; l < lines.size(); ++l )
    {
      const Profiles p = roadsBeside( grey, lines[l], object, options );
      const std::optional<std::vector<double>> shifts = smoothedShifts( p, options );
      if ( !shifts )
        continue;
      std::vector<double> widths;
      for ( double w : p.roadWidth )
        if ( w > 0.0 )
          widths.push_back( w );
      const double roadWidth = median( widths );
      const std::vector<Eigen::Vector2d> moved = movedCourse( p, *shifts, lines[l], std::max( 8.0, roadWidth ), options.stepPx );
      ++summary.moved;
      // the road found twice: another line is there (the others as they are now, moved or cut)
      const std::vector<bool> on = onOthers( moved, pieces, l, std::max( 2.0, 0.25 * roadWidth ) );
      if ( std::count( on.begin(), on.end(), true ) >= options.duplicateShare * static_cast<double>( on.size() ) )
      {
        pieces[l].clear();
        ++summary.duplicates;
        continue;
      }
      const std::vector<bool> repeated = longRuns( on, options.stepPx, std::max( 8.0, roadWidth ) );
      summary.repeatsCut += std::find( repeated.begin(), repeated.end(), true ) != repeated.end();
      pieces[l] = withoutRepeats( lines[l], moved, repeated, options.stepPx, std::max( 12.0, 2.0 * roadWidth ), options.toleranceDp );
    }
    for ( std::vector<CompiledPolygon> &line : pieces )
      for ( CompiledPolygon &piece : line )
        summary.lines.push_back( std::move( piece ) );
    return summary;
  }

} // namespace geostation

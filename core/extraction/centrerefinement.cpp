/***************************************************************************
  centrerefinement.cpp - the final lines moved onto the band's centre
 ***************************************************************************/
#include "extraction/centrerefinement.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>

#include "imageproc/edgeprimitives.h"

namespace geostation
{

  void CentreRefinementOptions::check() const
  {
    if ( !( stepPx >= 0.5 && stepPx <= 20.0 ) )
      throw std::invalid_argument( "the centre refinement's profile step must be 0.5-20 px" );
    if ( !( searchPx > 0.0 && searchPx <= 10.0 ) )
      throw std::invalid_argument( "the centre refinement's search must be 0-10 px" );
    if ( !( widthTolerance >= 0.0 && widthTolerance <= 1.0 ) || !( widthTolerancePx >= 0.0 && widthTolerancePx <= 20.0 ) )
      throw std::invalid_argument( "the centre refinement's width tolerances must be 0-1 (fraction) and 0-20 px" );
    if ( fitHalfWindow < 0 || minSupport < 1 || minSupport > 2 * fitHalfWindow + 1 )
      throw std::invalid_argument( "the centre refinement's median window must hold at least its minimum support" );
    if ( !( toleranceDp > 0.0 && toleranceDp <= 2.0 ) )
      throw std::invalid_argument( "the centre refinement's simplification tolerance must be 0-2 px" );
  }

  namespace
  {
    //! A polyline by arc length.
    class ArcLength
    {
      public:
        explicit ArcLength( const std::vector<Eigen::Vector2d> &line )
          : mLine( line )
        {
          mAt.push_back( 0.0 );
          for ( size_t i = 1; i < line.size(); ++i )
            mAt.push_back( mAt.back() + ( line[i] - line[i - 1] ).norm() );
        }
        double length() const { return mAt.back(); }
        Eigen::Vector2d pointAt( double s ) const
        {
          s = std::clamp( s, 0.0, length() );
          const size_t i = std::min<size_t>( std::upper_bound( mAt.begin(), mAt.end(), s ) - mAt.begin(), mAt.size() - 1 );
          if ( i == 0 )
            return mLine.front();
          const double span = mAt[i] - mAt[i - 1];
          return span > 0.0 ? mLine[i - 1] + ( s - mAt[i - 1] ) / span * ( mLine[i] - mLine[i - 1] ) : mLine[i];
        }

      private:
        const std::vector<Eigen::Vector2d> &mLine;
        std::vector<double> mAt;
    };

    //! The band's centre across `direction` nearest `at` within the search, relative to `at` (px), or nothing.
    std::optional<CrossSection> bandCentreNear( const GreyTiles &image, const Eigen::Vector2d &at, const Eigen::Vector2d &direction, const LineObjectOptions &object,
                                          double searchPx )
    {
      const int half = static_cast<int>( std::ceil( object.maxWidthPx + searchPx ) ) + 4;
      const GreyWindow window = image.around( at, half + 4 );
      const std::vector<double> profile = sampleCrossProfile( window.pixels, window.toWindow( at ), direction, half, object.polarity, 1.0, 3 );
      std::optional<CrossSection> best;
      for ( const CrossSection &c : findCrossSections( profile, object.minWidthPx, object.maxWidthPx, 0.5 * object.minContrast, 2.0 * object.maxVariation ) )
        if ( std::abs( c.offsetPx ) <= searchPx && ( !best || std::abs( c.offsetPx ) < std::abs( best->offsetPx ) ) )
          best = c;
      return best;
    }

    //! The value at 0 of a polynomial (degree 0-2) fitted to (t, d) by least squares, with `keep` choosing the points.
    double fitAtZero( const std::vector<std::pair<double, double>> &points, const std::vector<bool> &keep, std::vector<double> *residuals )
    {
      int used = 0;
      for ( bool k : keep )
        used += k;
      const int terms = used >= 6 ? 3 : used >= 3 ? 2 : 1;
      Eigen::MatrixXd a( used, terms );
      Eigen::VectorXd b( used );
      for ( size_t k = 0, row = 0; k < points.size(); ++k )
        if ( keep[k] )
        {
          for ( int j = 0; j < terms; ++j )
            a( row, j ) = std::pow( points[k].first, j );
          b( row++ ) = points[k].second;
        }
      const Eigen::VectorXd x = a.colPivHouseholderQr().solve( b );
      residuals->clear();
      for ( const auto &[t, d] : points )
      {
        double value = 0.0;
        for ( int j = 0; j < terms; ++j )
          value += x( j ) * std::pow( t, j );
        residuals->push_back( d - value );
      }
      return x( 0 );
    }

    /**
     * The shift across the line at each sample that puts it on the band: a
     * quadratic through the band's centres found within the window around
     * it, in the sample's own frame (along, across), fitted again without
     * the centres it leaves far off. Measured from the sample itself, so a
     * kink the line took round a car is straightened by the centres on
     * either side of it. Nothing where too few centres were found.
     */
    std::vector<std::optional<double>> fittedShifts( const std::vector<Eigen::Vector2d> &at, const std::vector<Eigen::Vector2d> &normal,
                                                     const std::vector<std::optional<double>> &found, double step, const CentreRefinementOptions &options )
    {
      const int n = static_cast<int>( at.size() );
      std::vector<std::optional<double>> shifts( n );
      const double reach = options.fitHalfWindow * step + 0.5 * step;
      std::vector<std::pair<double, double>> points;
      std::vector<double> residuals;
      for ( int i = 0; i < n; ++i )
      {
        if ( normal[i].norm() < 0.5 )
          continue;
        const Eigen::Vector2d along( normal[i].y(), -normal[i].x() );
        points.clear();
        for ( int k = std::max( 0, i - options.fitHalfWindow ); k <= std::min( n - 1, i + options.fitHalfWindow ); ++k )
          if ( found[k] && normal[k].norm() > 0.5 )
          {
            const Eigen::Vector2d centre = at[k] + *found[k] * normal[k] - at[i];
            if ( std::abs( centre.dot( along ) ) <= reach )
              points.emplace_back( centre.dot( along ), centre.dot( normal[i] ) );
          }
        if ( static_cast<int>( points.size() ) < options.minSupport )
          continue;
        std::vector<bool> keep( points.size(), true );
        double shift = fitAtZero( points, keep, &residuals );
        std::vector<double> spread;
        for ( double r : residuals )
          spread.push_back( std::abs( r ) );
        std::nth_element( spread.begin(), spread.begin() + spread.size() / 2, spread.end() );
        const double limit = std::max( 0.75, 3.0 * 1.4826 * spread[spread.size() / 2] );
        int kept = 0;
        for ( size_t k = 0; k < points.size(); ++k )
          kept += ( keep[k] = std::abs( residuals[k] ) <= limit );
        if ( kept >= options.minSupport && kept < static_cast<int>( points.size() ) )
          shift = fitAtZero( points, keep, &residuals );
        shifts[i] = std::clamp( shift, -options.searchPx - 1.0, options.searchPx + 1.0 );
      }
      return shifts;
    }

    //! A line's samples every `step` along it, with their normals (zero where the course is undefined).
    void sampleLine( const std::vector<Eigen::Vector2d> &line, int count, std::vector<Eigen::Vector2d> &at, std::vector<Eigen::Vector2d> &normal )
    {
      const ArcLength arc( line );
      const double step = arc.length() / ( count - 1 );
      at.assign( count, Eigen::Vector2d::Zero() );
      normal.assign( count, Eigen::Vector2d::Zero() );
      for ( int i = 0; i < count; ++i )
      {
        at[i] = arc.pointAt( i * step );
        // the course over a few pixels either side: the pixel staircase's own turns do not count
        const Eigen::Vector2d along = arc.pointAt( i * step + 4.0 ) - arc.pointAt( i * step - 4.0 );
        if ( along.norm() > 1e-6 )
          normal[i] = normalOf( along.normalized() );
      }
    }

    //! The band's centre near each sample, as an offset along its normal, where the band has the line's own width.
    std::vector<std::optional<double>> bandCentres( const GreyTiles &image, const std::vector<Eigen::Vector2d> &at, const std::vector<Eigen::Vector2d> &normal,
                                                    const LineObjectOptions &object, const CentreRefinementOptions &options, int &profiles )
    {
      const size_t count = at.size();
      std::vector<std::optional<CrossSection>> sections( count );
      for ( size_t i = 0; i < count; ++i )
        if ( normal[i].norm() > 0.5 )
        {
          sections[i] = bandCentreNear( image, at[i], Eigen::Vector2d( normal[i].y(), -normal[i].x() ), object, options.searchPx );
          ++profiles;
        }
      // a car on the road, a shadow across one side or a marking beside it makes the band wider or narrower
      // there: only sections of the line's own width count
      std::vector<double> widths;
      for ( const std::optional<CrossSection> &c : sections )
        if ( c )
          widths.push_back( c->widthPx );
      std::vector<std::optional<double>> found( count );
      if ( widths.empty() )
        return found;
      std::nth_element( widths.begin(), widths.begin() + widths.size() / 2, widths.end() );
      const double width = widths[widths.size() / 2];
      for ( size_t i = 0; i < count; ++i )
        if ( sections[i] && std::abs( sections[i]->widthPx - width ) <= std::max( options.widthTolerancePx, options.widthTolerance * width ) )
          found[i] = sections[i]->offsetPx;
      return found;
    }

    /**
     * The samples moved by their shifts. Across a stretch without one (a car
     * the band's width cannot be measured past, a shadow over the road): a
     * short stretch, up to `bridgePx`, runs straight between the moved
     * samples either side, so a kink round the car goes; a longer one keeps
     * its course, the shifts either side fading out over `fadePx` (carried
     * along it, they moved lines in a shadow off the road on the simulated
     * pairs).
     */
    std::vector<Eigen::Vector2d> movedSamples( const std::vector<Eigen::Vector2d> &at, const std::vector<Eigen::Vector2d> &normal,
                                               const std::vector<std::optional<double>> &shifts, double step, double bridgePx, double fadePx )
    {
      const int n = static_cast<int>( at.size() );
      std::vector<Eigen::Vector2d> moved = at;
      for ( int i = 0; i < n; ++i )
        if ( shifts[i] )
          moved[i] = at[i] + *shifts[i] * normal[i];
      for ( int i = 0; i < n; )
      {
        if ( shifts[i] )
        {
          ++i;
          continue;
        }
        int end = i;
        while ( end < n && !shifts[end] )
          ++end;
        const int before = i - 1, after = end; // supported samples either side (-1, n: none)
        for ( int k = i; k < end; ++k )
        {
          if ( before >= 0 && after < n && ( after - before ) * step <= bridgePx )
            moved[k] = moved[before] + double( k - before ) / ( after - before ) * ( moved[after] - moved[before] );
          else
          {
            // the shift of the nearer side, fading out over `fadePx`
            double shift = 0.0;
            if ( before >= 0 )
              shift += *shifts[before] * std::max( 0.0, 1.0 - ( k - before ) * step / fadePx );
            if ( after < n )
              shift += *shifts[after] * std::max( 0.0, 1.0 - ( after - k ) * step / fadePx );
            moved[k] = at[k] + shift * normal[k];
          }
        }
        i = end;
      }
      return moved;
    }
  } // namespace

  CentreRefinementSummary refineLineCentres( const GreyTiles &image, const std::vector<CompiledPolygon> &lines, const LineObjectOptions &object,
                                             const CentreRefinementOptions &options )
  {
    options.check();
    object.check();
    CentreRefinementSummary summary;
    double shiftSum = 0.0;
    for ( const CompiledPolygon &line : lines )
    {
      CompiledPolygon moved = line;
      const double length = line.pixels.size() < 2 ? 0.0 : ArcLength( line.pixels ).length();
      if ( length < 2.0 * options.stepPx )
      {
        summary.lines.push_back( moved );
        continue;
      }
      const int count = std::max( 2, static_cast<int>( std::round( length / options.stepPx ) ) + 1 );
      const double step = length / ( count - 1 );
      std::vector<Eigen::Vector2d> at, normal;
      sampleLine( line.pixels, count, at, normal );
      const std::vector<std::optional<double>> found = bandCentres( image, at, normal, object, options, summary.profiles );
      for ( const std::optional<double> &f : found )
        summary.bandFound += f.has_value();
      const std::vector<Eigen::Vector2d> onBand = movedSamples( at, normal, fittedShifts( at, normal, found, step, options ), step, 2.0 * object.maxWidthPx,
                                                           0.5 * object.maxWidthPx );
      // an end at an intersection stays where the branches meet: the move grows over the widest road's width
      const double ramp = std::max( 2.0, object.maxWidthPx );
      std::vector<Eigen::Vector2d> pixels;
      for ( int i = 0; i < count; ++i )
      {
        double weight = 1.0;
        if ( line.startEnd == PolygonEnd::Intersection )
          weight = std::min( weight, i * step / ramp );
        if ( line.endEnd == PolygonEnd::Intersection )
          weight = std::min( weight, ( count - 1 - i ) * step / ramp );
        pixels.push_back( at[i] + weight * ( onBand[i] - at[i] ) );
        shiftSum += ( pixels.back() - at[i] ).norm();
      }
      moved.pixels = douglasPeucker( pixels, options.toleranceDp );
      summary.lines.push_back( moved );
    }
    summary.meanShiftPx = summary.profiles > 0 ? shiftSum / summary.profiles : 0.0;
    return summary;
  }

} // namespace geostation

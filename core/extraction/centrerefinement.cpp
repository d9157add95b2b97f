/***************************************************************************
  centrerefinement.cpp - the final lines moved onto the band's centre
 ***************************************************************************/
#include "extraction/centrerefinement.h"

#include <algorithm>
#include <array>
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
      for ( const CrossSection &c : findCrossSections( profile, object.minWidthPx, object.maxWidthPx, 0.5 * object.minContrast, 2.0 * object.maxVariation, false, object.polarity ) )
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
      // the line's width from every eighth sample over the whole range of widths, then every sample
      // looked at only for bands of about that width (a wide range costs in every profile)
      LineObjectOptions aroundWidth = object;
      {
        std::vector<double> coarse;
        for ( size_t i = 0; i < count; i += 8 )
          if ( normal[i].norm() > 0.5 )
            if ( const std::optional<CrossSection> c = bandCentreNear( image, at[i], Eigen::Vector2d( normal[i].y(), -normal[i].x() ), object, options.searchPx ) )
              coarse.push_back( c->widthPx );
        if ( coarse.size() >= 3 )
        {
          std::nth_element( coarse.begin(), coarse.begin() + coarse.size() / 2, coarse.end() );
          const double width = coarse[coarse.size() / 2];
          aroundWidth.minWidthPx = std::max( object.minWidthPx, 0.6 * width );
          aroundWidth.maxWidthPx = std::max( aroundWidth.minWidthPx, std::min( object.maxWidthPx, 1.6 * width + 2.0 ) );
        }
      }
      std::vector<std::optional<CrossSection>> sections( count );
      for ( size_t i = 0; i < count; ++i )
        if ( normal[i].norm() > 0.5 )
        {
          sections[i] = bandCentreNear( image, at[i], Eigen::Vector2d( normal[i].y(), -normal[i].x() ), aroundWidth, options.searchPx );
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

  namespace
  {
    //! A line sampled every `step` and its samples moved onto the band (no ramp at its ends yet).
    struct MovedLine
    {
      std::vector<Eigen::Vector2d> at, onBand;
      double step = 0.0;
    };

    //! The straight line (point, unit normal) through the moved samples `from`-`to` px from a line's end, or nothing.
    std::optional<std::pair<Eigen::Vector2d, Eigen::Vector2d>> branchNearEnd( const MovedLine &line, bool atStart, double from, double to )
    {
      std::vector<Eigen::Vector2d> points;
      const int n = static_cast<int>( line.onBand.size() );
      for ( int i = 0; i < n; ++i )
      {
        const double s = ( atStart ? i : n - 1 - i ) * line.step;
        if ( s >= from && s <= to )
          points.push_back( line.onBand[i] );
      }
      if ( points.size() < 4 )
        return std::nullopt;
      Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
      for ( const Eigen::Vector2d &p : points )
        centroid += p / static_cast<double>( points.size() );
      Eigen::Matrix2d scatter = Eigen::Matrix2d::Zero();
      for ( const Eigen::Vector2d &p : points )
        scatter += ( p - centroid ) * ( p - centroid ).transpose();
      const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eigen( scatter );
      return std::make_pair( centroid, Eigen::Vector2d( eigen.eigenvectors().col( 0 ) ) ); // the smallest spread: across
    }

    /**
     * Where the branches meeting at each intersection cross once they are on
     * their bands: the point nearest (least squares) the straight lines
     * fitted to each branch's moved samples `from` px from it on (over `reach`);
     * held near where it was along branches that are nearly parallel, and
     * left there with fewer than two branches or a move over `maxMove`.
     * `junctions[line][0/1]`: the index of its start's / end's junction, or -1;
     * `centres`: where each junction was.
     */
    std::vector<Eigen::Vector2d> movedJunctions( const std::vector<CompiledPolygon> &lines, const std::vector<MovedLine> &moved, double from, double reach,
                                                 double maxMove, std::vector<std::array<int, 2>> &junctions, std::vector<Eigen::Vector2d> &centres )
    {
      centres.clear();
      junctions.assign( lines.size(), { -1, -1 } );
      for ( size_t l = 0; l < lines.size(); ++l )
        for ( int e = 0; e < 2; ++e )
        {
          if ( ( e == 0 ? lines[l].startEnd : lines[l].endEnd ) != PolygonEnd::Intersection || lines[l].pixels.empty() )
            continue;
          const Eigen::Vector2d end = e == 0 ? lines[l].pixels.front() : lines[l].pixels.back();
          int found = -1;
          for ( size_t j = 0; j < centres.size() && found < 0; ++j )
            if ( ( centres[j] - end ).norm() <= 2.0 )
              found = static_cast<int>( j );
          if ( found < 0 )
          {
            found = static_cast<int>( centres.size() );
            centres.push_back( end );
          }
          junctions[l][e] = found;
        }
      std::vector<Eigen::Vector2d> result = centres;
      for ( size_t j = 0; j < centres.size(); ++j )
      {
        Eigen::Matrix2d normalEquations = Eigen::Matrix2d::Zero();
        Eigen::Vector2d rightSide = Eigen::Vector2d::Zero();
        int branches = 0;
        for ( size_t l = 0; l < lines.size(); ++l )
          for ( int e = 0; e < 2; ++e )
            if ( junctions[l][e] == static_cast<int>( j ) )
              if ( const auto branch = branchNearEnd( moved[l], e == 0, from, from + reach ) )
              {
                const Eigen::Matrix2d across = branch->second * branch->second.transpose();
                normalEquations += across;
                rightSide += across * branch->first;
                ++branches;
              }
        if ( branches < 2 )
          continue;
        // a weak pull to where it was: along two nearly parallel branches nothing else places it
        const double pull = 0.05;
        normalEquations += pull * Eigen::Matrix2d::Identity();
        rightSide += pull * centres[j];
        const Eigen::Vector2d crossing = normalEquations.ldlt().solve( rightSide );
        if ( crossing.allFinite() && ( crossing - centres[j] ).norm() <= maxMove )
          result[j] = crossing;
      }
      return result;
    }
  } // namespace

  CentreRefinementSummary refineLineCentres( const GreyTiles &image, const std::vector<CompiledPolygon> &lines, const LineObjectOptions &object,
                                             const CentreRefinementOptions &options )
  {
    options.check();
    object.check();
    CentreRefinementSummary summary;
    std::vector<MovedLine> moved( lines.size() );
    for ( size_t l = 0; l < lines.size(); ++l )
    {
      const CompiledPolygon &line = lines[l];
      const double length = line.pixels.size() < 2 ? 0.0 : ArcLength( line.pixels ).length();
      if ( length < 2.0 * options.stepPx )
        continue;
      const int count = std::max( 2, static_cast<int>( std::round( length / options.stepPx ) ) + 1 );
      MovedLine &m = moved[l];
      m.step = length / ( count - 1 );
      std::vector<Eigen::Vector2d> normal;
      sampleLine( line.pixels, count, m.at, normal );
      const std::vector<std::optional<double>> found = bandCentres( image, m.at, normal, object, options, summary.profiles );
      for ( const std::optional<double> &f : found )
        summary.bandFound += f.has_value();
      m.onBand = movedSamples( m.at, normal, fittedShifts( m.at, normal, found, m.step, options ), m.step, 2.0 * object.maxWidthPx, 0.5 * object.maxWidthPx );
    }
    // an end at an intersection goes where its branches, moved, cross (their lines fitted from the widest road's
    // width to three times that from it: nearer, the profiles see the junction's mouth); the line's own move grows
    // from that over half the widest road's width (over the whole width: 0.940 / 0.972 on the ground on the
    // preset pair instead of 0.945 / 0.980)
    const double reachOfJunction = std::max( 2.0, object.maxWidthPx );
    const double ramp = 0.5 * reachOfJunction;
    std::vector<std::array<int, 2>> junctionOf;
    std::vector<Eigen::Vector2d> before;
    const std::vector<Eigen::Vector2d> junctions = movedJunctions( lines, moved, reachOfJunction, 2.0 * reachOfJunction, 0.5 * reachOfJunction, junctionOf, before );
    for ( size_t j = 0; j < junctions.size(); ++j )
      summary.junctions.emplace_back( before[j], junctions[j] );
    double shiftSum = 0.0;
    for ( size_t l = 0; l < lines.size(); ++l )
    {
      CompiledPolygon line = lines[l];
      const MovedLine &m = moved[l];
      if ( m.at.empty() )
      {
        // too short to profile: only its ends at an intersection go with it
        if ( junctionOf[l][0] >= 0 )
          line.pixels.front() = junctions[junctionOf[l][0]];
        if ( junctionOf[l][1] >= 0 )
          line.pixels.back() = junctions[junctionOf[l][1]];
        summary.lines.push_back( line );
        continue;
      }
      const int count = static_cast<int>( m.at.size() );
      const Eigen::Vector2d startMove = junctionOf[l][0] >= 0 ? Eigen::Vector2d( junctions[junctionOf[l][0]] - m.at.front() ) : Eigen::Vector2d::Zero();
      const Eigen::Vector2d endMove = junctionOf[l][1] >= 0 ? Eigen::Vector2d( junctions[junctionOf[l][1]] - m.at.back() ) : Eigen::Vector2d::Zero();
      std::vector<Eigen::Vector2d> pixels;
      for ( int i = 0; i < count; ++i )
      {
        // 0 at an intersection's end, 1 a ramp from it
        const double fromStart = line.startEnd == PolygonEnd::Intersection ? std::min( 1.0, i * m.step / ramp ) : 1.0;
        const double fromEnd = line.endEnd == PolygonEnd::Intersection ? std::min( 1.0, ( count - 1 - i ) * m.step / ramp ) : 1.0;
        double toStart = 1.0 - fromStart, toEnd = 1.0 - fromEnd; // how much of each junction's move the sample takes
        if ( toStart + toEnd > 1.0 )
        {
          // a line shorter than two ramps between two junctions: from one move to the other
          toStart = double( count - 1 - i ) / ( count - 1 );
          toEnd = 1.0 - toStart;
        }
        const double weight = std::min( fromStart, fromEnd );
        pixels.push_back( m.at[i] + weight * ( m.onBand[i] - m.at[i] ) + toStart * startMove + toEnd * endMove );
        shiftSum += ( pixels.back() - m.at[i] ).norm();
      }
      line.pixels = douglasPeucker( pixels, options.toleranceDp );
      summary.lines.push_back( line );
    }
    summary.meanShiftPx = summary.profiles > 0 ? shiftSum / summary.profiles : 0.0;
    return summary;
  }

  std::vector<Eigen::Vector2d> CentreRefinementSummary::movedIntersections( const std::vector<Eigen::Vector2d> &intersections ) const
  {
    std::vector<Eigen::Vector2d> moved = intersections;
    for ( Eigen::Vector2d &x : moved )
    {
      double nearest = 2.0;
      Eigen::Vector2d to = x;
      for ( const auto &[from, went] : junctions )
        if ( ( from - x ).norm() <= nearest )
        {
          nearest = ( from - x ).norm();
          to = went;
        }
      x = to;
    }
    return moved;
  }

} // namespace geostation

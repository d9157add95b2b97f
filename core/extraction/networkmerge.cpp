/***************************************************************************
  networkmerge.cpp - the road networks of overlapping pairs made one
 ***************************************************************************/
#include "extraction/networkmerge.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <stdexcept>

#include <Eigen/Geometry>

#include "geometry/polyline.h"

namespace geostation
{

  void NetworkMergeOptions::check() const
  {
    if ( !( toleranceM >= 0.0 ) || !( minToleranceM >= 0.0 ) || !( minPieceM >= 0.0 ) )
      throw std::invalid_argument( "the merge's tolerances and shortest piece must not be negative (metres)" );
    if ( !( sampleM > 0.0 ) )
      throw std::invalid_argument( "the merge's sample spacing must be positive (metres)" );
    if ( !( parallelDeg > 0.0 && parallelDeg < 90.0 ) )
      throw std::invalid_argument( "the merge's parallel angle must lie between 0 and 90 degrees" );
  }

  double MergedNetworkLine::lengthM() const
  {
    return polylineLengthXY( points );
  }

  namespace
  {
    //! A merged line while merging: each vertex knows the pair whose line it came from.
    struct Working
    {
      std::vector<Eigen::Vector3d> points;
      std::vector<int> origin; //!< per vertex: index of the pair
      double sigmaM = 0.0;
      std::set<std::string> pairs;
      bool removed = false;
      Eigen::AlignedBox2d box; //!< of the points (updateBox())
    };

    //! The nearest point of a polyline (XY) to `p`.
    struct Nearest
    {
      double distance = std::numeric_limits<double>::infinity();
      double along = 0.0;     //!< XY arc length to it
      size_t segment = 0;
      Eigen::Vector3d point = Eigen::Vector3d::Zero();
      Eigen::Vector2d direction = Eigen::Vector2d::UnitX();
    };

    Nearest nearestOn( const std::vector<Eigen::Vector3d> &line, const Eigen::Vector2d &p )
    {
      Nearest best;
      if ( line.size() < 2 )
        return best;
      const NearestOnPolyline<Eigen::Vector2d> n = nearestOnPolylineXY( line, p );
      const Eigen::Vector3d &a = line[n.segment], &b = line[n.segment + 1];
      best.distance = n.distance;
      best.along = n.t * ( b - a ).head<2>().norm();
      for ( size_t i = 0; i < n.segment; ++i )
        best.along += ( line[i + 1] - line[i] ).head<2>().norm();
      best.segment = n.segment;
      best.point = a + n.t * ( b - a );
      best.direction = n.direction.isZero() ? Eigen::Vector2d::UnitX() : n.direction;
      return best;
    }

    //! The line between arc lengths `from` and `to` (XY), its own vertices kept in between.
    std::vector<Eigen::Vector3d> cut( const std::vector<Eigen::Vector3d> &line, double from, double to )
    {
      std::vector<Eigen::Vector3d> out;
      double along = 0.0;
      for ( size_t i = 0; i + 1 < line.size(); ++i )
      {
        const double length = ( line[i + 1] - line[i] ).head<2>().norm();
        const auto at = [&]( double s ) { return length > 0.0 ? Eigen::Vector3d( line[i] + ( s - along ) / length * ( line[i + 1] - line[i] ) ) : line[i]; };
        if ( out.empty() && from <= along + length )
          out.push_back( at( std::max( from, along ) ) );
        if ( !out.empty() )
        {
          if ( to <= along + length )
          {
            out.push_back( at( to ) );
            break;
          }
          out.push_back( line[i + 1] );
        }
        along += length;
      }
      out.erase( std::unique( out.begin(), out.end(), []( const Eigen::Vector3d &a, const Eigen::Vector3d &b ) { return ( a - b ).norm() < 1e-9; } ), out.end() );
      return out;
    }

    //! Points every `step` along a line (XY), its end included, with their arc lengths and directions.
    struct Sample
    {
      Eigen::Vector2d point, direction;
      double along;
    };

    std::vector<Sample> samplesAlong( const std::vector<Eigen::Vector3d> &line, double step )
    {
      std::vector<Sample> out;
      const double total = polylineLengthXY( line );
      const int n = std::max( 1, static_cast<int>( std::ceil( total / step ) ) );
      size_t segment = 0;
      double segmentStart = 0.0;
      for ( int k = 0; k <= n; ++k )
      {
        const double s = total * k / n;
        // the segment holding s (zero-length segments skipped)
        while ( segment + 2 < line.size() && segmentStart + ( line[segment + 1] - line[segment] ).head<2>().norm() < s )
        {
          segmentStart += ( line[segment + 1] - line[segment] ).head<2>().norm();
          ++segment;
        }
        const Eigen::Vector2d a = line[segment].head<2>(), ab = line[segment + 1].head<2>() - a;
        const double length = ab.norm();
        const Eigen::Vector2d direction = length > 0.0 ? Eigen::Vector2d( ab / length ) : Eigen::Vector2d::UnitX();
        out.push_back( { a + direction * std::clamp( s - segmentStart, 0.0, length ), direction, s } );
      }
      return out;
    }

    void updateBox( Working &w )
    {
      w.box.setEmpty();
      for ( const Eigen::Vector3d &p : w.points )
        w.box.extend( Eigen::Vector2d( p.head<2>() ) );
    }

    //! Merges pairs' lines into `lines` (see the file comment).
    class Merger
    {
      public:
        Merger( const NetworkMergeOptions &options ) : mOptions( options ), mCosParallel( std::cos( options.parallelDeg * M_PI / 180.0 ) ) {}

        void add( const PairNetworkLine &line, int pairIndex, const std::string &pair, NetworkMergeSummary &summary );
        std::vector<Working> &lines() { return mLines; }

      private:
        double toleranceFor( double sigmaA, double sigmaB ) const
        {
          return mOptions.toleranceM > 0.0 ? mOptions.toleranceM : std::max( mOptions.minToleranceM, 3.0 * std::max( sigmaA, sigmaB ) );
        }
        //! The merged line (of another pair's making there) that a sample repeats, or -1.
        int covering( const Sample &s, double sigmaM, int pairIndex ) const;
        //! Attaches the end of line `piece` (its start or its end) to line `target`: continued or a junction.
        void attach( int piece, bool atStart, int target, NetworkMergeSummary &summary );

        const NetworkMergeOptions &mOptions;
        const double mCosParallel;
        std::vector<Working> mLines;
    };

    int Merger::covering( const Sample &s, double sigmaM, int pairIndex ) const
    {
      int best = -1;
      double bestDistance = std::numeric_limits<double>::infinity();
      for ( size_t m = 0; m < mLines.size(); ++m )
      {
        const Working &w = mLines[m];
        if ( w.removed )
          continue;
        const double tolerance = toleranceFor( sigmaM, w.sigmaM );
        if ( w.box.exteriorDistance( s.point ) > tolerance )
          continue;
        const Nearest n = nearestOn( w.points, s.point );
        if ( n.distance > tolerance || n.distance >= bestDistance || w.origin[n.segment] == pairIndex )
          continue;
        if ( std::abs( n.direction.dot( s.direction ) ) < mCosParallel )
          continue; // crossing, not repeating
        best = static_cast<int>( m );
        bestDistance = n.distance;
      }
      return best;
    }

    void Merger::attach( int piece, bool atStart, int target, NetworkMergeSummary &summary )
    {
      Working &p = mLines[piece], &m = mLines[target];
      const Eigen::Vector3d end = atStart ? p.points.front() : p.points.back();
      const Eigen::Vector3d inner = atStart ? p.points[1] : p.points[p.points.size() - 2];
      const Eigen::Vector2d away = ( end - inner ).head<2>().normalized(); // the piece's direction out through this end
      const Nearest n = nearestOn( m.points, end.head<2>() );
      const double reach = toleranceFor( p.sigmaM, m.sigmaM ) + 2.0 * mOptions.sampleM;
      const double total = polylineLengthXY( m.points );
      const Eigen::Vector2d mEndDirection = ( m.points.back() - m.points[m.points.size() - 2] ).head<2>().normalized();
      const Eigen::Vector2d mStartDirection = ( m.points.front() - m.points[1] ).head<2>().normalized();
      const bool atMEnd = n.along >= total - reach && -away.dot( mEndDirection ) >= mCosParallel;
      const bool atMStart = n.along <= reach && -away.dot( mStartDirection ) >= mCosParallel;
      if ( atMEnd || atMStart )
      {
        // one line: m's end turned to meet the piece's end; the piece's points beyond m's end follow
        std::vector<Eigen::Vector3d> first = m.points, second = p.points;
        std::vector<int> firstOrigin = m.origin, secondOrigin = p.origin;
        if ( atMStart )
        {
          std::reverse( first.begin(), first.end() );
          std::reverse( firstOrigin.begin(), firstOrigin.end() );
        }
        if ( !atStart )
        {
          std::reverse( second.begin(), second.end() );
          std::reverse( secondOrigin.begin(), secondOrigin.end() );
        }
        const Eigen::Vector2d onward = ( first.back() - first[first.size() - 2] ).head<2>().normalized();
        for ( size_t k = 0; k < second.size(); ++k )
          if ( ( second[k] - first.back() ).head<2>().dot( onward ) > 1e-6 )
          {
            first.push_back( second[k] );
            firstOrigin.push_back( secondOrigin[k] );
          }
        m.points = first;
        m.origin = firstOrigin;
        updateBox( m );
        m.sigmaM = std::max( m.sigmaM, p.sigmaM );
        m.pairs.insert( p.pairs.begin(), p.pairs.end() );
        p.removed = true;
        ++summary.bordersJoined;
        return;
      }
      // a junction: the piece ends on m, and m has the node too
      ( atStart ? p.points.front() : p.points.back() ) = n.point;
      const bool onVertex = ( n.point - m.points[n.segment] ).head<2>().norm() < 1e-6 || ( n.point - m.points[n.segment + 1] ).head<2>().norm() < 1e-6;
      if ( !onVertex )
      {
        m.points.insert( m.points.begin() + static_cast<long>( n.segment ) + 1, n.point );
        m.origin.insert( m.origin.begin() + static_cast<long>( n.segment ) + 1, m.origin[n.segment] );
      }
      updateBox( p );
      ++summary.junctions;
    }

    void Merger::add( const PairNetworkLine &line, int pairIndex, const std::string &pair, NetworkMergeSummary &summary )
    {
      const double total = polylineLengthXY( line.points );
      summary.lengthInM += total;
      ++summary.linesIn;
      if ( line.points.size() < 2 || !( total > 0.0 ) )
        return;
      const std::vector<Sample> samples = samplesAlong( line.points, mOptions.sampleM );
      std::vector<int> cover( samples.size() );
      for ( size_t i = 0; i < samples.size(); ++i )
        cover[i] = covering( samples[i], line.sigmaM, pairIndex );
      const double minPiece = mOptions.minPieceM > 0.0 ? mOptions.minPieceM : 2.0 * toleranceFor( line.sigmaM, 0.0 );
      // a repeat is not broken by a sample or two that wander off its direction (a line wavering along a kerb)
      for ( size_t i = 1; i < samples.size(); )
      {
        size_t j = i;
        while ( j < samples.size() && cover[j] < 0 )
          ++j;
        if ( j > i && cover[i - 1] >= 0 && j < samples.size() && samples[j].along - samples[i - 1].along <= 3.0 * mOptions.sampleM + 1e-9 )
          std::fill( cover.begin() + static_cast<long>( i ), cover.begin() + static_cast<long>( j ), cover[i - 1] );
        i = j + 1;
      }
      // a short repeat (a road crossing at a small angle) is no duplicate
      for ( size_t i = 0; i < samples.size(); )
      {
        size_t j = i;
        while ( j < samples.size() && ( cover[j] >= 0 ) == ( cover[i] >= 0 ) )
          ++j;
        if ( cover[i] >= 0 && samples[j - 1].along - samples[i].along < minPiece && !( i == 0 && j == samples.size() ) )
          std::fill( cover.begin() + static_cast<long>( i ), cover.begin() + static_cast<long>( j ), -1 );
        i = j;
      }
      for ( size_t i = 0; i < samples.size(); )
      {
        size_t j = i;
        while ( j < samples.size() && ( cover[j] >= 0 ) == ( cover[i] >= 0 ) )
          ++j;
        if ( cover[i] >= 0 )
        {
          // repeated: its pair joins the lines it repeats
          for ( size_t k = i; k < j; ++k )
            mLines[cover[k]].pairs.insert( pair );
          summary.duplicateLengthM += samples[j - 1].along - samples[i].along + ( j < samples.size() ? mOptions.sampleM : 0.0 );
          i = j;
          continue;
        }
        // a piece of its own, from the last covered sample before it to the first after it
        const int before = i > 0 ? cover[i - 1] : -1, after = j < samples.size() ? cover[j] : -1;
        const double from = samples[i > 0 ? i - 1 : i].along, to = samples[j < samples.size() ? j : j - 1].along;
        if ( to - from >= minPiece || ( before < 0 && after < 0 ) )
        {
          Working w;
          w.points = cut( line.points, from, to );
          w.origin.assign( w.points.size(), pairIndex );
          w.sigmaM = line.sigmaM;
          w.pairs.insert( pair );
          updateBox( w );
          if ( w.points.size() >= 2 )
          {
            mLines.push_back( w );
            const int piece = static_cast<int>( mLines.size() - 1 );
            if ( before >= 0 )
              attach( piece, true, before, summary );
            // the piece may have become the end of `before`'s line (continued): that line's end is the piece's
            const int holder = mLines[piece].removed ? before : piece;
            if ( after >= 0 && holder != after )
              attach( holder, false, after, summary );
          }
        }
        else
          summary.duplicateLengthM += to - from;
        i = j;
      }
    }
  } // namespace

  NetworkMergeSummary mergeNetworks( const std::vector<PairNetwork> &pairs, const NetworkMergeOptions &options )
  {
    options.check();
    std::vector<const PairNetwork *> ordered;
    for ( const PairNetwork &p : pairs )
      ordered.push_back( &p );
    std::sort( ordered.begin(), ordered.end(), []( const PairNetwork *a, const PairNetwork *b ) { return a->pair < b->pair; } );
    for ( size_t i = 1; i < ordered.size(); ++i )
      if ( ordered[i]->pair == ordered[i - 1]->pair )
        throw std::invalid_argument( "two pairs are named " + ordered[i]->pair + ": each pair's network once" );

    NetworkMergeSummary summary;
    Merger merger( options );
    for ( size_t p = 0; p < ordered.size(); ++p )
      for ( const PairNetworkLine &line : ordered[p]->lines )
        merger.add( line, static_cast<int>( p ), ordered[p]->pair, summary );
    for ( const Working &w : merger.lines() )
      if ( !w.removed && w.points.size() >= 2 )
        summary.lines.push_back( { w.points, w.sigmaM, std::vector<std::string>( w.pairs.begin(), w.pairs.end() ) } );
    return summary;
  }

} // namespace geostation

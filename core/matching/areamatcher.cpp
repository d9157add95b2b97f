/***************************************************************************
  areamatcher.cpp - epipolar band and 2-D correlation search, then LSM
 ***************************************************************************/
#include "matching/areamatcher.h"

#include <algorithm>
#include <cmath>
#include <set>

namespace geostation
{
  namespace
  {
    struct Candidate
    {
      int col, row;
      int along; //!< index along the curve, for the jump rule and peak separation
    };

    //! Integer pixels (col, row index) of the curve at 1 px steps and of its parallels.
    std::vector<Candidate> bandCandidates( const std::vector<Eigen::Vector2d> &curve, int halfWidth )
    {
      std::vector<Candidate> out;
      std::set<std::pair<int, int>> seen;
      int along = 0;
      for ( size_t i = 0; i + 1 < curve.size(); ++i )
      {
        const Eigen::Vector2d a = curve[i], b = curve[i + 1];
        const double length = ( b - a ).norm();
        if ( length <= 0.0 )
          continue;
        const Eigen::Vector2d direction = ( b - a ) / length, normal( -direction.y(), direction.x() );
        const int steps = std::max( 1, static_cast<int>( std::ceil( length ) ) );
        for ( int s = 0; s < steps; ++s )
        {
          const Eigen::Vector2d p = a + direction * ( length * s / steps );
          bool added = false;
          for ( int o = -halfWidth; o <= halfWidth; ++o )
          {
            const Eigen::Vector2d q = p + normal * o;
            const int col = static_cast<int>( std::floor( q.x() ) ), row = static_cast<int>( std::floor( q.y() ) );
            if ( seen.insert( { col, row } ).second )
            {
              out.push_back( { col, row, along } );
              added = true;
            }
          }
          along += added ? 1 : 0;
        }
      }
      return out;
    }

    constexpr double kCorrelationSigmaPx = 0.5; //!< the precision of a correlation peak without LSM (thesis: about a pixel at worst)

    //! Parabola refinement around an integer peak, then LSM; fills the result.
    void refine( const MatchImage &reference, const Eigen::Vector2d &pixelInReference, const MatchImage &search, const CorrelationTemplate &target,
                 int col, int row, const AreaMatchOptions &options, AreaMatch &result )
    {
      const auto scoreAt = [&]( int c, int r ) { return target.score( search, c, r ).value_or( result.score ); };
      const double dx = parabolaPeakOffset( scoreAt( col - 1, row ), result.score, scoreAt( col + 1, row ) );
      const double dy = parabolaPeakOffset( scoreAt( col, row - 1 ), result.score, scoreAt( col, row + 1 ) );
      // the template is centred on the reference pixel's centre; carry the reference point's offset from it over
      const Eigen::Vector2d offset = pixelInReference - Eigen::Vector2d( std::floor( pixelInReference.x() ) + 0.5, std::floor( pixelInReference.y() ) + 0.5 );
      result.correlationPixel = Eigen::Vector2d( col + 0.5 + dx, row + 0.5 + dy ) + offset;
      result.pixelInImage = result.correlationPixel;
      if ( result.score < options.minScore )
      {
        result.reason = "best correlation " + std::to_string( result.score ).substr( 0, 5 ) + " is below the threshold " + std::to_string( options.minScore ).substr( 0, 4 );
        return;
      }
      result.sigmaPx = kCorrelationSigmaPx;
      if ( options.lsm )
      {
        result.lsm = leastSquaresMatch( reference, pixelInReference, search, result.correlationPixel, options.lsmOptions );
        if ( result.lsm.converged )
        {
          result.pixelInImage = result.lsm.pixelInImage;
          result.sigmaPx = result.lsm.sigmaPxMax();
        }
        else
        {
          // a line or an edge: LSM cannot fix the shift along it; the correlation peak stands, at its precision
          result.reason = "least-squares matching could not refine: " + result.lsm.reason;
        }
      }
      result.matched = true;
    }

    AreaMatch searchCandidates( const MatchImage &reference, const Eigen::Vector2d &pixelInReference, const MatchImage &search,
                                const std::vector<Candidate> &candidates, const AreaMatchOptions &options, bool jumps )
    {
      AreaMatch result;
      if ( !reference.canSample( pixelInReference.x(), pixelInReference.y() ) )
      {
        result.reason = "the point lies outside the reference image";
        return result;
      }
      const int centreCol = static_cast<int>( std::floor( pixelInReference.x() ) ), centreRow = static_cast<int>( std::floor( pixelInReference.y() ) );
      const CorrelationTemplate target( reference, centreCol, centreRow, options.windowWidth, options.windowHeight, options.measure );
      if ( !target.valid() )
      {
        result.reason = target.reason();
        return result;
      }
      if ( candidates.empty() )
      {
        result.reason = "no search position in the search image";
        return result;
      }
      double best = -2.0;
      const Candidate *bestCandidate = nullptr;
      std::vector<std::pair<double, const Candidate *>> scored;
      int skipUntil = -1;
      for ( const Candidate &candidate : candidates )
      {
        if ( jumps && candidate.along < skipUntil )
          continue;
        const std::optional<double> score = target.score( search, candidate.col, candidate.row );
        ++result.candidates;
        if ( !score )
          continue;
        scored.emplace_back( *score, &candidate );
        if ( *score > best )
        {
          best = *score;
          bestCandidate = &candidate;
        }
        if ( jumps )
          skipUntil = candidate.along + ( *score < 0.2 ? 4 : *score < 0.4 ? 3 : *score < 0.6 ? 2 : 0 );
      }
      if ( !bestCandidate )
      {
        result.reason = "every search window leaves the search image or is flat";
        return result;
      }
      result.score = best;
      // the best score of a separate peak: more than 2 px from the best
      for ( const auto &[score, candidate] : scored )
        if ( std::hypot( candidate->col - bestCandidate->col, candidate->row - bestCandidate->row ) > 2.5 )
          result.secondScore = std::max( result.secondScore, score );
      // the separate peaks, best first (greedy: a candidate joins when no better one is within 2.5 px)
      std::sort( scored.begin(), scored.end(), []( const auto &a, const auto &b ) { return a.first > b.first; } );
      const Eigen::Vector2d offset = pixelInReference - Eigen::Vector2d( centreCol + 0.5, centreRow + 0.5 );
      for ( const auto &[score, candidate] : scored )
      {
        const Eigen::Vector2d at( candidate->col + 0.5, candidate->row + 0.5 );
        bool separate = true;
        for ( const auto &peak : result.peaks )
          separate = separate && ( peak.first - offset - at ).norm() > 2.5;
        if ( separate )
          result.peaks.emplace_back( at + offset, score );
        if ( result.peaks.size() >= 8 )
          break;
      }
      refine( reference, pixelInReference, search, target, bestCandidate->col, bestCandidate->row, options, result );
      return result;
    }
  }

  AreaMatch matchAlongEpipolarBand( const MatchImage &reference, const Eigen::Vector2d &pixelInReference, const MatchImage &search,
                                    const std::vector<Eigen::Vector2d> &curve, const AreaMatchOptions &options )
  {
    return searchCandidates( reference, pixelInReference, search, bandCandidates( curve, std::max( 0, options.bandHalfWidthPx ) ), options, options.jumpRule );
  }

  AreaMatch matchAroundPosition( const MatchImage &reference, const Eigen::Vector2d &pixelInReference, const MatchImage &search,
                                 const Eigen::Vector2d &approximate, double radiusPx, const AreaMatchOptions &options )
  {
    std::vector<Candidate> candidates;
    const int r = static_cast<int>( std::ceil( radiusPx ) );
    const int c0 = static_cast<int>( std::floor( approximate.x() ) ), r0 = static_cast<int>( std::floor( approximate.y() ) );
    for ( int dr = -r; dr <= r; ++dr )
      for ( int dc = -r; dc <= r; ++dc )
        if ( dc * dc + dr * dr <= radiusPx * radiusPx + 1e-9 )
          candidates.push_back( { c0 + dc, r0 + dr, 0 } );
    return searchCandidates( reference, pixelInReference, search, candidates, options, false );
  }

} // namespace geostation

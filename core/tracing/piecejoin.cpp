/***************************************************************************
  piecejoin.cpp - one line from the pieces traced from several seeds
 ***************************************************************************/
#include "tracing/piecejoin.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>

#include "geometry/polyline.h"

namespace geostation
{

  void PieceJoinOptions::check() const
  {
    if ( !( sigmaFactor > 0.0 ) || !( minToleranceM >= 0.0 ) || !( agreeM >= 0.0 ) || agreeVertices < 1 )
      throw std::invalid_argument( "the pieces' sigma factor and agreeing vertices must be positive, their tolerances not negative" );
  }

  namespace
  {
    //! Appends `next` to `line` (a's vertices up to where `next` starts), reporting how they agree.
    void joinNext( JoinedLine &line, double previousSigmaM, const std::string &previousName, const TracedPiece &next, const PieceJoinOptions &options,
                   std::vector<PieceDisagreement> &disagreements )
    {
      const double allowed = std::max( options.minToleranceM, options.sigmaFactor * std::hypot( previousSigmaM, next.sigmaM ) );
      const NearestOnPolyline<Eigen::Vector3d> start = nearestOnPolyline( line.points, next.points.front() );
      const bool atEnd = start.segment + 2 == line.points.size() && start.t >= 1.0;
      if ( atEnd && start.distance > allowed )
      {
        // the earlier piece stops short of the next one's start
        disagreements.push_back( { line.lineId, previousName, next.name, start.distance, allowed, 0.0, true } );
        line.points.insert( line.points.end(), next.points.begin(), next.points.end() );
        return;
      }
      // the earlier piece beyond the next one's start, compared with it
      // the last vertex kept: the one before the next piece's start (a vertex at its start gives way to it)
      const size_t at = start.t >= 1.0 ? start.segment + 1 : start.segment;
      const size_t keep = ( start.t <= 0.0 || start.t >= 1.0 ) && at > 0 ? at - 1 : at;
      // where the two run together (the later one has settled onto the earlier) for at least agreeVertices in a row,
      // the earlier piece is kept up to the last vertex of the last such run and the later one goes on from there:
      // the earlier piece has had more stations to settle, and each trace's first stations (the later one's) and
      // last stations (the earlier one's) are its least settled, which is where such runs end
      size_t lastEnd = 0, runLength = 0;
      bool agreed = false;
      for ( size_t i = keep + 1; i < line.points.size(); ++i )
      {
        runLength = nearestOnPolyline( next.points, line.points[i] ).distance <= options.agreeM ? runLength + 1 : 0;
        if ( runLength >= static_cast<size_t>( options.agreeVertices ) )
        {
          lastEnd = i;
          agreed = true;
        }
      }
      if ( agreed )
      {
        // from the next piece's first vertex beyond the earlier piece's vertex at the switch
        // (a switch onto the next piece's vertex itself: from the one after it)
        const NearestOnPolyline<Eigen::Vector3d> on = nearestOnPolyline( next.points, line.points[lastEnd] );
        const size_t from = on.segment + ( on.t >= 1.0 ? 2 : 1 );
        line.points.resize( lastEnd + 1 );
        if ( from < next.points.size() )
          line.points.insert( line.points.end(), next.points.begin() + static_cast<long>( from ), next.points.end() );
        return;
      }
      // they never run together: the next piece from its start, and how far the earlier one was from it
      double worst = start.distance;
      for ( size_t i = keep + 1; i < line.points.size(); ++i )
        worst = std::max( worst, nearestOnPolyline( next.points, line.points[i] ).distance );
      if ( worst > allowed )
        disagreements.push_back( { line.lineId, previousName, next.name, worst, allowed, polylineLengthXY( line.points, keep ), false } );
      line.points.resize( keep + 1 );
      line.points.insert( line.points.end(), next.points.begin(), next.points.end() );
    }
  } // namespace

  PieceJoinSummary joinTracedPieces( const std::vector<TracedPiece> &pieces, const PieceJoinOptions &options )
  {
    options.check();
    std::map<std::string, std::vector<const TracedPiece *>> byLine;
    for ( const TracedPiece &p : pieces )
      if ( p.points.size() >= 2 )
        byLine[p.lineId].push_back( &p );
    PieceJoinSummary summary;
    for ( auto &[lineId, linePieces] : byLine )
    {
      std::sort( linePieces.begin(), linePieces.end(), []( const TracedPiece *a, const TracedPiece *b ) { return a->order < b->order; } );
      for ( size_t i = 1; i < linePieces.size(); ++i )
        if ( linePieces[i]->order == linePieces[i - 1]->order )
          throw std::invalid_argument( "line " + lineId + " has two pieces in place " + std::to_string( linePieces[i]->order ) + ": each seed once" );
      JoinedLine line;
      line.lineId = lineId;
      line.points = linePieces.front()->points;
      line.sigmaM = linePieces.front()->sigmaM;
      line.pieces = 1;
      for ( size_t i = 1; i < linePieces.size(); ++i )
      {
        joinNext( line, linePieces[i - 1]->sigmaM, linePieces[i - 1]->name, *linePieces[i], options, summary.disagreements );
        line.sigmaM = std::max( line.sigmaM, linePieces[i]->sigmaM );
        ++line.pieces;
      }
      summary.lines.push_back( line );
    }
    return summary;
  }

} // namespace geostation

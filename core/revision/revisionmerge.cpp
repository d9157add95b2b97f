/***************************************************************************
  revisionmerge.cpp - the revisions of one map by overlapping pairs, as one
 ***************************************************************************/
#include "revision/revisionmerge.h"

#include <algorithm>
#include <map>
#include <numeric>
#include <set>
#include <stdexcept>

namespace geostation
{

  namespace
  {
    constexpr double kSameM = 1e-6; // two places along a map road closer than this are one

    //! A piece of one pair: where it is in the input.
    struct PieceRef
    {
      size_t pair = 0;  //!< index into the pairs in the order of their names
      size_t piece = 0; //!< index into that pair's pieces
    };

    //! A course cut to a stretch along the map road, with what each vertex carries.
    struct CutCourse
    {
      std::vector<Eigen::Vector3d> course, sigma;
      std::vector<bool> stereo;
      std::vector<double> along;
    };

    /**
     * The part of `p`'s course between t0 and t1 along the map road: its
     * vertices there, and points interpolated where its segments cross t0
     * and t1 (sigma the larger of the two ends', each axis).
     */
    CutCourse cutAlong( const RevisedPiece &p, double t0, double t1 )
    {
      CutCourse out;
      const std::vector<double> &a = p.alongMapM;
      const bool withSigma = p.sigmaM.size() == p.course.size();
      const auto push = [&]( size_t i, double t ) {
        const double span = a[i + 1] - a[i];
        const double w = span > kSameM ? std::clamp( ( t - a[i] ) / span, 0.0, 1.0 ) : ( t > a[i] ? 1.0 : 0.0 );
        if ( !out.along.empty() && std::abs( out.along.back() - t ) < kSameM )
          return;
        out.course.push_back( w <= 0.0 ? p.course[i] : w >= 1.0 ? p.course[i + 1] : Eigen::Vector3d( p.course[i] + w * ( p.course[i + 1] - p.course[i] ) ) );
        out.along.push_back( t );
        if ( withSigma )
          out.sigma.push_back( w <= 0.0 ? p.sigmaM[i] : w >= 1.0 ? p.sigmaM[i + 1] : Eigen::Vector3d( p.sigmaM[i].cwiseMax( p.sigmaM[i + 1] ) ) );
        const bool stereoI = i < p.heightByStereo.size() && p.heightByStereo[i], stereoJ = i + 1 < p.heightByStereo.size() && p.heightByStereo[i + 1];
        out.stereo.push_back( w <= 0.0 ? stereoI : w >= 1.0 ? stereoJ : stereoI && stereoJ );
      };
      for ( size_t i = 0; i + 1 < p.course.size(); ++i )
      {
        if ( a[i + 1] < a[i] || a[i + 1] < t0 - kSameM || a[i] > t1 + kSameM )
          continue;
        push( i, std::max( a[i], t0 ) );
        push( i, std::min( a[i + 1], t1 ) );
      }
      return out;
    }

    //! The piece of `candidates` that tells most about a stretch (file comment); candidates is not empty.
    PieceRef mostTelling( const std::vector<PieceRef> &candidates, const std::vector<const PairRevision *> &pairs )
    {
      return *std::min_element( candidates.begin(), candidates.end(), [&]( const PieceRef &x, const PieceRef &y ) {
        const RevisedPiece &px = pairs[x.pair]->pieces[x.piece], &py = pairs[y.pair]->pieces[y.piece];
        if ( revisionRank( px.status ) != revisionRank( py.status ) )
          return revisionRank( px.status ) < revisionRank( py.status );
        if ( px.evidence != py.evidence )
          return px.evidence > py.evidence;
        return std::make_pair( x.pair, x.piece ) < std::make_pair( y.pair, y.piece );
      } );
    }

    //! One stretch of a road between two consecutive places where some piece begins or ends.
    struct Stretch
    {
      double t0 = 0.0, t1 = 0.0;
      PieceRef chosen;
    };

    //! Stretches of one status, one after the other, as one merged piece.
    MergedRevisionPiece pieceOfRun( const std::vector<Stretch> &run, const std::vector<const PairRevision *> &pairs, const std::vector<size_t> &inputIndex )
    {
      MergedRevisionPiece merged;
      const RevisedPiece &first = pairs[run.front().chosen.pair]->pieces[run.front().chosen.piece];
      merged.piece.road = first.road;
      merged.piece.status = first.status;
      merged.piece.fromM = run.front().t0;
      merged.piece.toM = run.back().t1;
      merged.pairIndex = inputIndex[run.front().chosen.pair];
      merged.pieceIndex = run.front().chosen.piece;
      double length = 0.0, evidence = 0.0, shift = 0.0;
      bool withSigma = true;
      std::set<size_t> pairsUsed;
      for ( const Stretch &s : run )
      {
        const RevisedPiece &p = pairs[s.chosen.pair]->pieces[s.chosen.piece];
        const double l = s.t1 - s.t0;
        length += l;
        evidence += l * p.evidence;
        shift += l * p.shiftM;
        pairsUsed.insert( s.chosen.pair );
        const CutCourse cut = cutAlong( p, s.t0, s.t1 );
        withSigma = withSigma && cut.sigma.size() == cut.course.size();
        for ( size_t k = 0; k < cut.course.size(); ++k )
        {
          // one stretch's last vertex is the next one's first where both come from one piece
          if ( !merged.piece.alongMapM.empty() && std::abs( merged.piece.alongMapM.back() - cut.along[k] ) < kSameM &&
               ( merged.piece.course.back() - cut.course[k] ).norm() < kSameM )
            continue;
          merged.piece.course.push_back( cut.course[k] );
          merged.piece.alongMapM.push_back( cut.along[k] );
          merged.piece.heightByStereo.push_back( cut.stereo[k] );
          if ( k < cut.sigma.size() )
            merged.piece.sigmaM.push_back( cut.sigma[k] );
        }
      }
      if ( !withSigma || merged.piece.sigmaM.size() != merged.piece.course.size() )
      {
        // some stretch kept the map's course: the piece has no measured sigma (as a single pair's would not)
        merged.piece.sigmaM.clear();
        merged.piece.heightByStereo.clear();
      }
      merged.piece.evidence = length > 0.0 ? evidence / length : first.evidence;
      merged.piece.shiftM = merged.piece.status == RevisionStatus::Moved && length > 0.0 ? shift / length : 0.0;
      for ( const size_t pair : pairsUsed )
        merged.pairs.push_back( pairs[pair]->pair );
      return merged;
    }

    void checkPiece( const PairRevision &pair, const RevisedPiece &p )
    {
      if ( p.alongMapM.size() != p.course.size() || p.fromM > p.toM + kSameM )
        throw std::invalid_argument( "a piece of pair " + pair.pair + " (map road " + std::to_string( p.road ) +
                                     ") does not say where it lies along the map road: revise the pair again" );
    }
  } // namespace

  int revisionRank( RevisionStatus status )
  {
    switch ( status )
    {
      case RevisionStatus::Confirmed: return 0;
      case RevisionStatus::Moved: return 1;
      case RevisionStatus::NotFound: return 2;
      case RevisionStatus::Occluded: return 3;
      case RevisionStatus::Outside: return 4;
      case RevisionStatus::InvalidGeometry: return 5;
    }
    return 5;
  }

  double RevisionMergeSummary::lengthM( RevisionStatus status ) const
  {
    double length = 0.0;
    for ( const MergedRevisionPiece &p : pieces )
      if ( p.piece.status == status )
        length += p.piece.toM - p.piece.fromM;
    return length;
  }

  RevisionMergeSummary mergeRevisions( const std::vector<PairRevision> &input )
  {
    // pairs by name; their pieces by road
    std::vector<size_t> order( input.size() );
    std::iota( order.begin(), order.end(), 0 );
    std::sort( order.begin(), order.end(), [&]( size_t x, size_t y ) { return input[x].pair < input[y].pair; } );
    std::vector<const PairRevision *> pairs;
    for ( size_t k = 0; k < order.size(); ++k )
    {
      if ( k > 0 && input[order[k]].pair == input[order[k - 1]].pair )
        throw std::invalid_argument( "two revisions come from one pair, " + input[order[k]].pair + ": give each pair once" );
      pairs.push_back( &input[order[k]] );
    }
    RevisionMergeSummary summary;
    std::map<size_t, std::vector<PieceRef>> byRoad;
    for ( size_t a = 0; a < pairs.size(); ++a )
      for ( size_t i = 0; i < pairs[a]->pieces.size(); ++i )
      {
        checkPiece( *pairs[a], pairs[a]->pieces[i] );
        byRoad[pairs[a]->pieces[i].road].push_back( { a, i } );
        ++summary.piecesIn;
      }

    for ( const auto &[road, refs] : byRoad )
    {
      const auto pieceOf = [&]( const PieceRef &r ) -> const RevisedPiece & { return pairs[r.pair]->pieces[r.piece]; };
      std::vector<PieceRef> valid;
      std::copy_if( refs.begin(), refs.end(), std::back_inserter( valid ), [&]( const PieceRef &r ) { return pieceOf( r ).status != RevisionStatus::InvalidGeometry; } );
      if ( valid.empty() )
      {
        // no pair could read the feature: once, as the first pair has it
        MergedRevisionPiece invalid;
        invalid.piece = pieceOf( refs.front() );
        invalid.pairIndex = order[refs.front().pair];
        invalid.pieceIndex = refs.front().piece;
        for ( const PieceRef &r : refs )
          if ( invalid.pairs.empty() || invalid.pairs.back() != pairs[r.pair]->pair )
            invalid.pairs.push_back( pairs[r.pair]->pair );
        summary.pieces.push_back( invalid );
        continue;
      }
      // the places where some piece begins or ends, and the stretches between them
      std::vector<double> cuts;
      for ( const PieceRef &r : valid )
      {
        cuts.push_back( pieceOf( r ).fromM );
        cuts.push_back( pieceOf( r ).toM );
      }
      std::sort( cuts.begin(), cuts.end() );
      cuts.erase( std::unique( cuts.begin(), cuts.end(), []( double x, double y ) { return y - x < kSameM; } ), cuts.end() );
      std::vector<Stretch> stretches;
      for ( size_t c = 0; c + 1 < cuts.size(); ++c )
      {
        const double t0 = cuts[c], t1 = cuts[c + 1];
        std::vector<PieceRef> covering;
        std::set<size_t> seeing;
        std::set<RevisionStatus> said;
        for ( const PieceRef &r : valid )
          if ( pieceOf( r ).fromM <= t0 + kSameM && pieceOf( r ).toM >= t1 - kSameM )
          {
            covering.push_back( r );
            const RevisionStatus s = pieceOf( r ).status;
            if ( s != RevisionStatus::Outside )
              seeing.insert( r.pair );
            if ( s == RevisionStatus::Confirmed || s == RevisionStatus::Moved || s == RevisionStatus::NotFound )
              said.insert( s );
          }
        if ( covering.empty() )
          continue; // no pair has a piece here (a stretch too short to keep): the road is split
        if ( seeing.size() > 1 )
        {
          summary.seenTwiceM += t1 - t0;
          if ( said.size() > 1 )
            summary.disagreedM += t1 - t0;
        }
        stretches.push_back( { t0, t1, mostTelling( covering, pairs ) } );
      }
      // consecutive stretches of one status, meeting, are one piece
      for ( size_t from = 0; from < stretches.size(); )
      {
        size_t to = from + 1;
        while ( to < stretches.size() && std::abs( stretches[to].t0 - stretches[to - 1].t1 ) < kSameM &&
                pieceOf( stretches[to].chosen ).status == pieceOf( stretches[from].chosen ).status )
          ++to;
        MergedRevisionPiece merged = pieceOfRun( std::vector<Stretch>( stretches.begin() + from, stretches.begin() + to ), pairs, order );
        if ( merged.piece.course.size() >= 2 )
          summary.pieces.push_back( std::move( merged ) );
        from = to;
      }
    }
    return summary;
  }

} // namespace geostation

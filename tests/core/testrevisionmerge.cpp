/***************************************************************************
  testrevisionmerge.cpp - one map revised by overlapping pairs, made one
  -------------------------------------------------------------------------
  Hand-made pieces along a straight map road (y = 0, x = 0..300 m, so the
  place along the road is x): measured courses a little beside it, with
  sigma, and the map's own course where a pair did not confirm or move it.
 ***************************************************************************/
#include <algorithm>
#include <random>

#include <gtest/gtest.h>

#include "revision/revisionmerge.h"

using namespace geostation;

namespace
{
  //! A piece of map road `road` from x = a to x = b; confirmed and moved ones at y = offset with sigma, a vertex every 10 m.
  RevisedPiece piece( RevisionStatus status, double a, double b, double offset = 0.0, double evidence = 1.0, size_t road = 7 )
  {
    RevisedPiece p;
    p.road = road;
    p.status = status;
    p.evidence = evidence;
    p.fromM = a;
    p.toM = b;
    const bool measured = status == RevisionStatus::Confirmed || status == RevisionStatus::Moved;
    p.shiftM = status == RevisionStatus::Moved ? std::abs( offset ) : 0.0;
    for ( double x = a; x <= b + 1e-9; x += 10.0 )
    {
      p.course.emplace_back( x, measured ? offset : 0.0, 300.0 );
      p.alongMapM.push_back( x );
      if ( measured )
      {
        p.sigmaM.emplace_back( 0.1 + x / 1000.0, 0.1, 0.2 );
        p.heightByStereo.push_back( true );
      }
    }
    return p;
  }

  std::vector<PairRevision> strip()
  {
    return { { "A", { piece( RevisionStatus::Confirmed, 0, 120, 0.1 ), piece( RevisionStatus::Outside, 120, 300 ) } },
             { "B", { piece( RevisionStatus::Outside, 0, 80 ), piece( RevisionStatus::Confirmed, 80, 220, -0.1 ), piece( RevisionStatus::Outside, 220, 300 ) } },
             { "C", { piece( RevisionStatus::Outside, 0, 180 ), piece( RevisionStatus::Confirmed, 180, 260, 0.2 ), piece( RevisionStatus::NotFound, 260, 300 ) } } };
  }

  double yAt( const RevisedPiece &p, double x )
  {
    for ( size_t k = 0; k < p.course.size(); ++k )
      if ( std::abs( p.course[k].x() - x ) < 1e-6 )
        return p.course[k].y();
    return std::nan( "" );
  }
} // namespace

TEST( RevisionMerge, OverlappingPairsMakeOneCourseAlongEachRoad )
{
  const RevisionMergeSummary s = mergeRevisions( strip() );
  ASSERT_EQ( s.pieces.size(), 2u );
  const RevisedPiece &confirmed = s.pieces[0].piece;
  EXPECT_EQ( confirmed.status, RevisionStatus::Confirmed );
  EXPECT_DOUBLE_EQ( confirmed.fromM, 0.0 );
  EXPECT_DOUBLE_EQ( confirmed.toM, 260.0 );
  EXPECT_EQ( s.pieces[0].pairs, ( std::vector<std::string> { "A", "B", "C" } ) );
  // each stretch from the pair that tells most, ties to the first by name: A to 120, B to 220, C to 260
  EXPECT_DOUBLE_EQ( yAt( confirmed, 50 ), 0.1 );
  EXPECT_DOUBLE_EQ( yAt( confirmed, 100 ), 0.1 );
  EXPECT_DOUBLE_EQ( yAt( confirmed, 150 ), -0.1 );
  EXPECT_DOUBLE_EQ( yAt( confirmed, 200 ), -0.1 );
  EXPECT_DOUBLE_EQ( yAt( confirmed, 240 ), 0.2 );
  ASSERT_EQ( confirmed.sigmaM.size(), confirmed.course.size() );
  ASSERT_EQ( confirmed.alongMapM.size(), confirmed.course.size() );
  for ( size_t k = 1; k < confirmed.course.size(); ++k )
    EXPECT_GE( confirmed.alongMapM[k], confirmed.alongMapM[k - 1] ) << "along the map road, in order";
  EXPECT_EQ( s.pieces[1].piece.status, RevisionStatus::NotFound );
  EXPECT_DOUBLE_EQ( s.pieces[1].piece.fromM, 260.0 );
  EXPECT_DOUBLE_EQ( s.pieces[1].piece.toM, 300.0 );
  EXPECT_EQ( s.pieces[1].pairs, ( std::vector<std::string> { "C" } ) );
  EXPECT_TRUE( s.pieces[1].piece.sigmaM.empty() ) << "the map's course has no measured sigma";
  EXPECT_DOUBLE_EQ( s.seenTwiceM, 80.0 ); // 80-120 and 180-220
  EXPECT_DOUBLE_EQ( s.disagreedM, 0.0 );
  EXPECT_DOUBLE_EQ( s.lengthM( RevisionStatus::Confirmed ), 260.0 );
  EXPECT_EQ( s.piecesIn, 8 );
}

TEST( RevisionMerge, ACutBetweenVerticesIsInterpolatedWithTheLargerSigma )
{
  std::vector<PairRevision> pairs = { { "A", { piece( RevisionStatus::Confirmed, 0, 100, 0.0 ) } },
                                      { "B", { piece( RevisionStatus::Outside, 0, 45 ), piece( RevisionStatus::Moved, 45, 100, 3.0 ) } } };
  const RevisionMergeSummary s = mergeRevisions( pairs );
  ASSERT_EQ( s.pieces.size(), 1u );
  const RevisedPiece &p = s.pieces[0].piece;
  // confirmed outranks moved everywhere: A's course, cut at B's 45 m between A's vertices at 40 and 50
  const auto at45 = std::find_if( p.alongMapM.begin(), p.alongMapM.end(), []( double t ) { return std::abs( t - 45.0 ) < 1e-9; } );
  ASSERT_NE( at45, p.alongMapM.end() );
  const size_t k = at45 - p.alongMapM.begin();
  EXPECT_NEAR( p.course[k].x(), 45.0, 1e-9 );
  EXPECT_NEAR( p.course[k].y(), 0.0, 1e-9 );
  EXPECT_DOUBLE_EQ( p.sigmaM[k].x(), 0.1 + 50.0 / 1000.0 ) << "the larger of its two ends'";
  EXPECT_EQ( p.course.size(), 12u ) << "0, 10, .., 40, 45, 50, .., 100: the cut adds one vertex and repeats none";
  EXPECT_DOUBLE_EQ( s.disagreedM, 55.0 );
}

TEST( RevisionMerge, TheStatusThatTellsMostWinsAndDisagreementIsCounted )
{
  // 0-40: not found by A, hidden in B, moved in C; 40-60: B confirms it; 60-100: A does not find it, B confirms it
  const std::vector<PairRevision> pairs = {
    { "A", { piece( RevisionStatus::NotFound, 0, 100 ) } },
    { "B", { piece( RevisionStatus::Occluded, 0, 40 ), piece( RevisionStatus::Confirmed, 40, 100, 0.0, 0.8 ) } },
    { "C", { piece( RevisionStatus::Moved, 0, 60, 5.0, 0.9 ), piece( RevisionStatus::Outside, 60, 100 ) } } };
  const RevisionMergeSummary s = mergeRevisions( pairs );
  ASSERT_EQ( s.pieces.size(), 2u );
  EXPECT_EQ( s.pieces[0].piece.status, RevisionStatus::Moved );
  EXPECT_DOUBLE_EQ( s.pieces[0].piece.toM, 40.0 );
  EXPECT_DOUBLE_EQ( s.pieces[0].piece.shiftM, 5.0 );
  EXPECT_DOUBLE_EQ( s.pieces[0].piece.evidence, 0.9 );
  EXPECT_EQ( s.pieces[0].pairs, ( std::vector<std::string> { "C" } ) );
  EXPECT_EQ( s.pieces[0].pairIndex, 2u );
  EXPECT_EQ( s.pieces[1].piece.status, RevisionStatus::Confirmed );
  EXPECT_DOUBLE_EQ( s.pieces[1].piece.fromM, 40.0 );
  EXPECT_DOUBLE_EQ( s.pieces[1].piece.toM, 100.0 );
  EXPECT_DOUBLE_EQ( s.disagreedM, 100.0 );
  EXPECT_DOUBLE_EQ( s.seenTwiceM, 100.0 );
}

TEST( RevisionMerge, TheOrderOfThePairsDoesNotMatter )
{
  const RevisionMergeSummary reference = mergeRevisions( strip() );
  std::vector<PairRevision> shuffled = strip();
  std::mt19937 random( 5 );
  for ( int trial = 0; trial < 5; ++trial )
  {
    std::shuffle( shuffled.begin(), shuffled.end(), random );
    const RevisionMergeSummary s = mergeRevisions( shuffled );
    ASSERT_EQ( s.pieces.size(), reference.pieces.size() );
    for ( size_t i = 0; i < s.pieces.size(); ++i )
    {
      EXPECT_EQ( s.pieces[i].pairs, reference.pieces[i].pairs );
      EXPECT_EQ( shuffled[s.pieces[i].pairIndex].pair, strip()[reference.pieces[i].pairIndex].pair ) << "the attributes' piece, named by its pair";
      ASSERT_EQ( s.pieces[i].piece.course.size(), reference.pieces[i].piece.course.size() );
      for ( size_t k = 0; k < s.pieces[i].piece.course.size(); ++k )
        EXPECT_EQ( s.pieces[i].piece.course[k], reference.pieces[i].piece.course[k] );
    }
  }
}

TEST( RevisionMerge, OnePairIsItsOwnMergeAndRoadsStaySeparate )
{
  PairRevision one { "A", { piece( RevisionStatus::Confirmed, 0, 100, 0.1, 1.0, 3 ), piece( RevisionStatus::NotFound, 100, 150, 0.0, 1.0, 3 ),
                            piece( RevisionStatus::Moved, 0, 50, 4.0, 0.7, 1 ) } };
  RevisedPiece invalid;
  invalid.road = 9;
  invalid.status = RevisionStatus::InvalidGeometry;
  one.pieces.push_back( invalid );
  const RevisionMergeSummary s = mergeRevisions( { one } );
  ASSERT_EQ( s.pieces.size(), 4u );
  EXPECT_EQ( s.pieces[0].piece.road, 1u ) << "roads in the order of their ids";
  EXPECT_EQ( s.pieces[0].pieceIndex, 2u );
  EXPECT_EQ( s.pieces[1].piece.road, 3u );
  EXPECT_EQ( s.pieces[1].piece.course, one.pieces[0].course );
  EXPECT_EQ( s.pieces[1].piece.sigmaM, one.pieces[0].sigmaM );
  EXPECT_EQ( s.pieces[2].piece.course, one.pieces[1].course );
  EXPECT_EQ( s.pieces[3].piece.status, RevisionStatus::InvalidGeometry );
  EXPECT_EQ( s.disagreedM, 0.0 );
}

TEST( RevisionMerge, BadInputIsOneSentence )
{
  EXPECT_THROW( mergeRevisions( { { "A", { piece( RevisionStatus::Confirmed, 0, 50 ) } }, { "A", { piece( RevisionStatus::Outside, 0, 50 ) } } } ), std::invalid_argument );
  RevisedPiece unplaced = piece( RevisionStatus::Confirmed, 0, 50 );
  unplaced.alongMapM.pop_back();
  EXPECT_THROW( mergeRevisions( { { "A", { unplaced } } } ), std::invalid_argument );
  EXPECT_TRUE( mergeRevisions( {} ).pieces.empty() );
}

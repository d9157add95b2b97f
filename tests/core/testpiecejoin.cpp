/***************************************************************************
  testpiecejoin.cpp - one line from pieces traced from several seeds
 ***************************************************************************/
#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

#include "tracing/piecejoin.h"

using namespace geostation;

namespace
{
  //! Along y = offset from x = from to x = to, a vertex every 5 m, at height 100.
  TracedPiece piece( const std::string &line, int order, double from, double to, double offset = 0.0, double sigma = 0.01 )
  {
    TracedPiece p;
    p.lineId = line;
    p.order = order;
    p.sigmaM = sigma;
    p.name = line + "#" + std::to_string( order );
    for ( double x = from; x <= to + 1e-9; x += 5.0 )
      p.points.emplace_back( x, offset, 100.0 );
    return p;
  }
} // namespace

TEST( PieceJoin, PiecesThatOverlapBecomeOneLine )
{
  // three seeds of one line at x = 0, 100, 200, each traced 20 m past the next; the pieces agree within 2 mm
  const std::vector<TracedPiece> pieces = { piece( "L1", 1, 0, 120 ), piece( "L1", 2, 100, 220, 0.002 ), piece( "L1", 3, 200, 300 ), piece( "L2", 1, 0, 50, 30.0 ) };
  PieceJoinSummary s = joinTracedPieces( pieces );
  ASSERT_EQ( s.lines.size(), 2u );
  const JoinedLine &l1 = s.lines[0];
  EXPECT_EQ( l1.lineId, "L1" );
  EXPECT_EQ( l1.pieces, 3 );
  EXPECT_DOUBLE_EQ( l1.points.front().x(), 0.0 );
  EXPECT_DOUBLE_EQ( l1.points.back().x(), 300.0 );
  for ( size_t i = 1; i < l1.points.size(); ++i )
    EXPECT_GT( l1.points[i].x(), l1.points[i - 1].x() ) << "no vertex twice, none going back";
  EXPECT_TRUE( s.disagreements.empty() );
  // whatever order they come in
  std::vector<TracedPiece> reversed = pieces;
  std::reverse( reversed.begin(), reversed.end() );
  const PieceJoinSummary r = joinTracedPieces( reversed );
  ASSERT_EQ( r.lines.size(), 2u );
  EXPECT_EQ( r.lines[0].points, l1.points );
}

TEST( PieceJoin, ThePieceThatCameThroughIsKeptUntilTheNextHasSettled )
{
  // the second piece, started from its seed at x = 100, runs 0.3 m off for its first 20 m, then on the first piece's vertices
  TracedPiece second = piece( "L", 2, 100, 250 );
  for ( Eigen::Vector3d &p : second.points )
    if ( p.x() < 120.0 )
      p.y() = 0.3;
  const PieceJoinSummary s = joinTracedPieces( { piece( "L", 1, 0, 160 ), second } );
  ASSERT_EQ( s.lines.size(), 1u );
  for ( const Eigen::Vector3d &p : s.lines[0].points )
    EXPECT_DOUBLE_EQ( p.y(), 0.0 ) << "at x = " << p.x();
  EXPECT_DOUBLE_EQ( s.lines[0].points.back().x(), 250.0 );
  EXPECT_TRUE( s.disagreements.empty() );
}

TEST( PieceJoin, TheEarlierPieceIsKeptToTheLastPlaceTheyAgree )
{
  // the first piece's last 10 m have not settled (0.2 m off); the second, settled by x = 105, still strays 5 cm at
  // x = 150 once: the earlier piece, with more stations behind it, is kept up to x = 190, where they last agree
  TracedPiece first = piece( "L", 1, 0, 200 );
  for ( Eigen::Vector3d &p : first.points )
    if ( p.x() > 190.0 )
      p.y() = 0.2;
  TracedPiece second = piece( "L", 2, 100, 300 );
  for ( Eigen::Vector3d &p : second.points )
    if ( p.x() < 105.0 || std::abs( p.x() - 150.0 ) < 1.0 )
      p.y() = p.x() < 105.0 ? 0.3 : 0.05;
  const PieceJoinSummary s = joinTracedPieces( { first, second } );
  ASSERT_EQ( s.lines.size(), 1u );
  for ( const Eigen::Vector3d &p : s.lines[0].points )
    EXPECT_DOUBLE_EQ( p.y(), 0.0 ) << "at x = " << p.x();
  EXPECT_DOUBLE_EQ( s.lines[0].points.back().x(), 300.0 );
  for ( size_t i = 1; i < s.lines[0].points.size(); ++i )
    EXPECT_GT( s.lines[0].points[i].x(), s.lines[0].points[i - 1].x() ) << "no vertex twice, none going back";
}

TEST( PieceJoin, PiecesThatDisagreeOrDoNotMeetAreReported )
{
  // the second piece 0.2 m off the first where they overlap (sigmas 1 cm: 4 cm allowed); the third starts 20 m after the second ends
  const PieceJoinSummary s = joinTracedPieces( { piece( "L", 1, 0, 120 ), piece( "L", 2, 100, 180, 0.2 ), piece( "L", 3, 200, 300, 0.2 ) } );
  ASSERT_EQ( s.lines.size(), 1u );
  ASSERT_EQ( s.disagreements.size(), 2u );
  const PieceDisagreement &off = s.disagreements[0], &gap = s.disagreements[1];
  EXPECT_EQ( off.first, "L#1" );
  EXPECT_EQ( off.second, "L#2" );
  EXPECT_FALSE( off.gap );
  EXPECT_NEAR( off.worstM, 0.2, 1e-9 );
  EXPECT_NEAR( off.allowedM, 3.0 * std::hypot( 0.01, 0.01 ), 1e-12 );
  EXPECT_GT( off.overlapM, 15.0 );
  EXPECT_TRUE( gap.gap );
  EXPECT_NEAR( gap.worstM, 20.0, 1e-9 );
  EXPECT_DOUBLE_EQ( s.lines[0].points.back().x(), 300.0 ); // joined all the same, straight across the gap
}

TEST( PieceJoin, BadInput )
{
  EXPECT_THROW( joinTracedPieces( { piece( "L", 1, 0, 50 ), piece( "L", 1, 40, 90 ) } ), std::invalid_argument );
  PieceJoinOptions bad;
  bad.sigmaFactor = 0.0;
  EXPECT_THROW( joinTracedPieces( {}, bad ), std::invalid_argument );
  TracedPiece dot = piece( "L", 1, 0, 0 ); // one point: left out
  EXPECT_TRUE( joinTracedPieces( { dot } ).lines.empty() );
}

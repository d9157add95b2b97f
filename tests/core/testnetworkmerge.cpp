/***************************************************************************
  testnetworkmerge.cpp - overlapping pairs' road networks made one
  -------------------------------------------------------------------------
  Three pairs along a strip, x = 0..600, 400..1000 and 800..1400 m: a main
  road along the strip seen by each pair over its part (found 0.2-0.3 m
  apart by neighbouring pairs), a road crossing it at x = 500 seen by the
  first two pairs, a side road that starts at the main road (a junction)
  in the second pair's part, and a road crossing the border between the
  second and third pairs at an angle, cut at each pair's edge.
 ***************************************************************************/
#include <algorithm>
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "extraction/networkmerge.h"

using namespace geostation;

namespace
{
  //! A straight line from a to b, a vertex every 10 m, moved by `offset` across it.
  PairNetworkLine straight( const Eigen::Vector2d &a, const Eigen::Vector2d &b, double offset, double sigma = 0.1 )
  {
    PairNetworkLine line;
    line.sigmaM = sigma;
    const Eigen::Vector2d d = ( b - a ).normalized(), normal( -d.y(), d.x() );
    const int n = std::max( 1, static_cast<int>( std::ceil( ( b - a ).norm() / 10.0 ) ) );
    for ( int k = 0; k <= n; ++k )
    {
      const Eigen::Vector2d p = a + ( b - a ) * ( static_cast<double>( k ) / n ) + offset * normal;
      line.points.emplace_back( p.x(), p.y(), 300.0 );
    }
    return line;
  }

  std::vector<PairNetwork> strip()
  {
    PairNetwork first { "S0001-S0002", {} }, second { "S0002-S0003", {} }, third { "S0003-S0004", {} };
    first.lines.push_back( straight( { 0, 0 }, { 600, 0 }, 0.0 ) );
    second.lines.push_back( straight( { 400, 0 }, { 1000, 0 }, 0.25 ) );
    third.lines.push_back( straight( { 800, 0 }, { 1400, 0 }, -0.2 ) );
    first.lines.push_back( straight( { 500, -300 }, { 500, 300 }, 0.0 ) ); // the crossing road, seen twice
    second.lines.push_back( straight( { 500, -300 }, { 500, 300 }, 0.3 ) );
    second.lines.push_back( straight( { 700, 0 }, { 700, 250 }, 0.0 ) );  // the side road from a junction
    second.lines.push_back( straight( { 850, -200 }, { 1000, -50 }, 0.0 ) ); // across the border, cut at x = 1000 ...
    third.lines.push_back( straight( { 830, -220 }, { 1100, 50 }, 0.2 ) ); // ... and seen from x = 830 on in the next pair
    // a road branching off the main road at x = 880, its line following the main road (there the second pair's) for 30 m first
    PairNetworkLine branch = straight( { 850, 0 }, { 880, 0 }, -0.2 );
    for ( const Eigen::Vector3d &p : straight( { 880, -0.2 }, { 1000, 119.8 }, 0.0 ).points )
      branch.points.push_back( p );
    third.lines.push_back( branch );
    return { first, second, third };
  }

  //! The merged lines within 2 m of a point, and the length of merged line lying within 2 m of another merged line, about parallel.
  int linesNear( const NetworkMergeSummary &s, const Eigen::Vector2d &p )
  {
    int n = 0;
    for ( const MergedNetworkLine &l : s.lines )
    {
      double best = 1e300;
      for ( size_t i = 0; i + 1 < l.points.size(); ++i )
      {
        const Eigen::Vector2d a = l.points[i].head<2>(), ab = l.points[i + 1].head<2>() - a;
        const double t = std::clamp( ( p - a ).dot( ab ) / ab.squaredNorm(), 0.0, 1.0 );
        best = std::min( best, ( a + t * ab - p ).norm() );
      }
      n += best < 2.0;
    }
    return n;
  }

  double totalLength( const NetworkMergeSummary &s )
  {
    double length = 0.0;
    for ( const MergedNetworkLine &l : s.lines )
      length += l.lengthM();
    return length;
  }
} // namespace

TEST( NetworkMerge, OneLinePerRoadAcrossOverlapsAndBorders )
{
  const NetworkMergeSummary s = mergeNetworks( strip() );
  // the main road: one line from 0 to 1400 m, found by all three pairs
  for ( const double x : { 10.0, 450.0, 590.0, 900.0, 1390.0 } )
    EXPECT_EQ( linesNear( s, { x, 0.0 } ), 1 ) << "at x = " << x;
  const auto main = std::find_if( s.lines.begin(), s.lines.end(), []( const MergedNetworkLine &l ) { return l.lengthM() > 1300.0; } );
  ASSERT_NE( main, s.lines.end() ) << "the main road is one line";
  EXPECT_EQ( main->pairs, ( std::vector<std::string> { "S0001-S0002", "S0002-S0003", "S0003-S0004" } ) );
  // the crossing road once, whole, crossing the main road
  EXPECT_EQ( linesNear( s, { 500.0, 200.0 } ), 1 );
  EXPECT_EQ( linesNear( s, { 500.0, -200.0 } ), 1 );
  // the side road, its node on the main road
  EXPECT_EQ( linesNear( s, { 700.0, 150.0 } ), 1 );
  // the road across the border: one line
  EXPECT_EQ( linesNear( s, { 950.0, -100.0 } ), 1 );
  EXPECT_EQ( linesNear( s, { 1050.0, 0.0 } ), 2 ); // itself and the main road, where it crosses
  const auto border = std::find_if( s.lines.begin(), s.lines.end(), []( const MergedNetworkLine &l ) {
    return l.points.front().y() < -150.0 || l.points.back().y() < -150.0;
  } );
  ASSERT_NE( border, s.lines.end() );
  EXPECT_GT( border->lengthM(), 330.0 ) << "from (830, -220) to (1100, 50): about 382 m";
  // the branch: from the main road's side (its node shared), not along it
  EXPECT_EQ( linesNear( s, { 940.0, 60.0 } ), 1 );
  EXPECT_EQ( linesNear( s, { 865.0, 0.0 } ), 1 );
  EXPECT_EQ( s.lines.size(), 5u ) << "main, crossing, side, across the border, branch";
  // nothing doubled: the merged length is the roads' length within a few metres
  const double roads = 1400.0 + 600.0 + 250.0 + std::hypot( 270.0, 270.0 ) + std::hypot( 120.0, 120.0 );
  std::printf( "merged %.0f m of %.0f m in; %.0f m dropped as duplicates; %d borders joined, %d junctions; roads %.0f m\n", totalLength( s ), s.lengthInM,
               s.duplicateLengthM, s.bordersJoined, s.junctions, roads );
  EXPECT_NEAR( totalLength( s ), roads, 0.02 * roads );
  EXPECT_GE( s.bordersJoined, 3 );
  EXPECT_GE( s.junctions, 1 );
}

TEST( NetworkMerge, TheSameWhateverTheOrderThePairsCameIn )
{
  std::vector<PairNetwork> pairs = strip();
  const NetworkMergeSummary first = mergeNetworks( pairs );
  std::reverse( pairs.begin(), pairs.end() );
  const NetworkMergeSummary reversed = mergeNetworks( pairs );
  ASSERT_EQ( first.lines.size(), reversed.lines.size() );
  for ( size_t i = 0; i < first.lines.size(); ++i )
  {
    ASSERT_EQ( first.lines[i].points.size(), reversed.lines[i].points.size() );
    for ( size_t k = 0; k < first.lines[i].points.size(); ++k )
      EXPECT_EQ( first.lines[i].points[k], reversed.lines[i].points[k] );
    EXPECT_EQ( first.lines[i].pairs, reversed.lines[i].pairs );
  }
}

TEST( NetworkMerge, BadOptionsAndTwoPairsOfOneName )
{
  NetworkMergeOptions bad;
  bad.sampleM = 0.0;
  EXPECT_THROW( mergeNetworks( strip(), bad ), std::invalid_argument );
  std::vector<PairNetwork> twice = strip();
  twice[1].pair = twice[0].pair;
  EXPECT_THROW( mergeNetworks( twice ), std::invalid_argument );
  // nothing in, nothing out; a line of one point is counted, not kept
  EXPECT_TRUE( mergeNetworks( {} ).lines.empty() );
  PairNetwork single { "a-b", { PairNetworkLine { { Eigen::Vector3d( 1, 2, 3 ) }, 0.1 } } };
  const NetworkMergeSummary s = mergeNetworks( { single } );
  EXPECT_TRUE( s.lines.empty() );
  EXPECT_EQ( s.linesIn, 1 );
}

// A road found by two pairs, the second's line wavering along it (a kink of 45 degrees every 5 m between 0.3 and
// 1.3 m off, as a line following a kerb does): the kinks do not break the repeat into pieces too short to be one,
// and the road is one line.
TEST( NetworkMerge, ARepeatThatWaversIsStillARepeat )
{
  PairNetwork first { "S0001-S0002", { straight( { 0, 0 }, { 300, 0 }, 0.0, 1.0 ) } }, second { "S0002-S0003", {} };
  PairNetworkLine wavering;
  wavering.sigmaM = 1.0;
  for ( int k = 0; k < 60; ++k )
  {
    const double y = k % 2 ? 1.3 : 0.3;
    wavering.points.emplace_back( 5.0 * k, y, 300.0 );
    wavering.points.emplace_back( 5.0 * k + 4.0, y, 300.0 );
  }
  second.lines.push_back( wavering );
  const NetworkMergeSummary s = mergeNetworks( { first, second } );
  ASSERT_EQ( s.lines.size(), 1u );
  EXPECT_NEAR( totalLength( s ), 300.0, 5.0 );
  EXPECT_EQ( s.lines[0].pairs, ( std::vector<std::string> { "S0001-S0002", "S0002-S0003" } ) );
  EXPECT_GT( s.duplicateLengthM, 280.0 );
}

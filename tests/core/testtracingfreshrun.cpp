/***************************************************************************
  testtracingfreshrun.cpp - road tracing on other simulated runs
  -------------------------------------------------------------------------
  The tracing tests share one simulated run; a method tuned on one run can
  fail on the next. Here the same lines are traced from one click each on
  runs with another scene, other worn patches and shadows, other noise and
  other pose errors (seeds 23 and 31, or GEOSTATION_TRACING_FRESH_SEED),
  and held to the same figures. On seed 23 the edge line once jumped 6.7 m
  across the road onto the lane line at a shadow (now cut by the corridor
  along the van's track) and, on seed 11, slid onto the kerb face beside
  it at a station's far end (now dropped by the lateral check). On seed 31
  the click on the edge line lands on a worn crack across the stripe,
  whose edge turned the seed's direction 20 degrees (now the directions
  along which the line is found furthest are tried).
 ***************************************************************************/
#include <cstdlib>

#include <gtest/gtest.h>

#include "highwaytracing.h"

using namespace geostation;
using namespace geostation::highwaytracing;

class TracingFreshRun : public ::testing::TestWithParam<uint32_t>
{
};

TEST_P( TracingFreshRun, HighwayLinesFromOneSeedEach )
{
  const char *fresh = std::getenv( "GEOSTATION_TRACING_FRESH_SEED" );
  const HighwayRun &run = highwayRun( fresh ? static_cast<uint32_t>( std::strtoul( fresh, nullptr, 10 ) ) : GetParam() );
  for ( const HighwayLine &c : kHighwayLines )
  {
    SCOPED_TRACE( c.name );
    const std::vector<Eigen::Vector3d> truth = joinedTruthLine( run.roads, c.prefix );
    ASSERT_GE( truth.size(), 2u );
    const RoadTraceSummary s = traceFromSeed( run, run.block, c.prefix, "S0001_FL", TraceMethod::Auto );
    const LineScore sc = score( s, truth, run, 0.10 );
    print( c.name, s, sc );
    EXPECT_GE( sc.buffer.completeness, c.minCompleteness );
    EXPECT_GE( sc.buffer.correctness, c.minCorrectness );
    EXPECT_EQ( s.stop, TraceStop::EndOfRun ) << s.message;
    EXPECT_GE( s.lengthM, 300.0 );
    EXPECT_LE( sc.rms15, c.maxRms15 );
    EXPECT_GE( sc.normalisedSd, 0.7 );
    EXPECT_LE( sc.normalisedSd, 1.4 );
  }
}

TEST_P( TracingFreshRun, KerbOuterEdgeFromOneSeed )
{
  const char *fresh = std::getenv( "GEOSTATION_TRACING_FRESH_SEED" );
  const HighwayRun &run = highwayRun( fresh ? static_cast<uint32_t>( std::strtoul( fresh, nullptr, 10 ) ) : GetParam() );
  const HighwayLine &c = kKerbOuterEdge;
  const std::vector<Eigen::Vector3d> truth = joinedTruthLine( run.roads, c.prefix );
  ASSERT_GE( truth.size(), 2u );
  const RoadTraceSummary s = traceFromSeed( run, run.block, c.prefix, "S0001_FL", TraceMethod::Auto );
  const LineScore sc = score( s, truth, run, 0.10 );
  print( c.name, s, sc );
  EXPECT_GE( sc.buffer.completeness, c.minCompleteness );
  EXPECT_GE( sc.buffer.correctness, c.minCorrectness );
  EXPECT_EQ( s.stop, TraceStop::EndOfRun ) << s.message;
  EXPECT_LE( sc.rms15, c.maxRms15 );
  EXPECT_GE( sc.normalisedSd, 0.7 );
  EXPECT_LE( sc.normalisedSd, 1.4 );
}

INSTANTIATE_TEST_SUITE_P( Seeds, TracingFreshRun, ::testing::Values( 23u, 31u ) );

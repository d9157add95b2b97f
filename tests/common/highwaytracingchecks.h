/***************************************************************************
  highwaytracingchecks.h - a highway line traced from one click, checked
  -------------------------------------------------------------------------
  The checks every run must pass for a line of highwaytracing.h, shared by
  the tracing tests on the default run and on the fresh runs.
 ***************************************************************************/
#ifndef GEOSTATION_TESTS_HIGHWAYTRACINGCHECKS_H
#define GEOSTATION_TESTS_HIGHWAYTRACINGCHECKS_H

#include <gtest/gtest.h>

#include "highwaytracing.h"

namespace geostation::highwaytracing
{
  /**
   * Traces `line` from one click (auto) in the first station's front-left
   * image and checks it: the whole run (300 m and more), its completeness,
   * correctness and RMS within 15 m, and honest sigmas (normalised sd
   * 0.7-1.4). Returns what was traced and its score.
   */
  inline std::pair<RoadTraceSummary, LineScore> expectWholeRunFromOneSeed( const HighwayRun &run, const HighwayLine &line )
  {
    SCOPED_TRACE( line.name );
    const std::vector<Eigen::Vector3d> truth = joinedTruthLine( run.roads, line.prefix );
    EXPECT_GE( truth.size(), 2u );
    const RoadTraceSummary s = traceFromSeed( run, run.block, line.prefix, "S0001_FL", TraceMethod::Auto );
    const LineScore sc = score( s, truth, run, 0.10 );
    print( line.name, s, sc );
    dumpVertices( line.name, s, run, line.prefix );
    EXPECT_EQ( s.stop, TraceStop::EndOfRun ) << s.message;
    EXPECT_GE( s.lengthM, 300.0 );
    EXPECT_GE( sc.buffer.completeness, line.minCompleteness );
    EXPECT_GE( sc.buffer.correctness, line.minCorrectness );
    EXPECT_LE( sc.rms15, line.maxRms15 );
    EXPECT_GE( sc.normalisedSd, 0.7 );
    EXPECT_LE( sc.normalisedSd, 1.4 );
    return { s, sc };
  }

} // namespace geostation::highwaytracing

#endif // GEOSTATION_TESTS_HIGHWAYTRACINGCHECKS_H

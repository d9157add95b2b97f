/***************************************************************************
  highwaytracing.h - road tracing on a simulated highway run, scored
  -------------------------------------------------------------------------
  The run the tracing tests share (simulated once per process and seed),
  where an operator would click, and the buffer method's score of a traced
  line against the simulator's truth.
 ***************************************************************************/
#ifndef GEOSTATION_TESTS_HIGHWAYTRACING_H
#define GEOSTATION_TESTS_HIGHWAYTRACING_H

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <limits>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <string>
#include <vector>
#include <unistd.h>

#include <Eigen/Core>

#include "io/block.h"
#include "linescoring.h"
#include "simulation/surveysimulator.h"
#include "tracing/roadtracer.h"

namespace geostation::highwaytracing
{
  struct HighwayRun
  {
    std::filesystem::path dir;
    Block block, truth;
    std::vector<TruthRoadLine> roads;
  };

  //! Simulates a run into `dir` and reads its block, truth block and truth road lines.
  inline HighwayRun simulateRun( SimulationOptions options, const std::filesystem::path &dir )
  {
    HighwayRun r;
    r.dir = dir;
    options.preset = SurveyPreset::Highway;
    options.outputDir = dir;
    simulateSurvey( options );
    r.block = Block::load( dir / "block.geostation.json" );
    r.truth = Block::load( dir / "truth.geostation.json" );
    r.roads = readTruthRoadLines( dir / "truth.gpkg" );
    return r;
  }

  /**
   * 32 stations every 10 m (310 m, through the 220 m curve), two forward
   * cameras at 1024 x 768, noise, blur, JPEG and a post-processed
   * trajectory's errors; simulated once per process and seed.
   */
  inline const HighwayRun &highwayRun( uint32_t seed )
  {
    static std::map<uint32_t, HighwayRun> runs;
    if ( auto it = runs.find( seed ); it != runs.end() )
      return it->second;
    SimulationOptions o;
    // GEOSTATION_TRACING_STATIONS shortens the run (the sanitizer stage: simulating 32 stations there takes six minutes)
    const char *stations = std::getenv( "GEOSTATION_TRACING_STATIONS" );
    o.stations = stations ? std::max( 8, std::atoi( stations ) ) : 32;
    o.stationSpacingM = 10.0;
    o.cameras = 2;
    o.imageWidth = 1024;
    o.imageHeight = 768;
    o.seed = seed;
    o.degradation.noiseSigma = 2.0;
    o.degradation.blurSigmaPx = 0.6;
    o.degradation.jpegQuality = 85;
    o.poseNoiseScale = 0.2; // a post-processed trajectory: 2 cm, 3 cm in height
    const std::filesystem::path dir = std::filesystem::temp_directory_path() / ( "geostation-tracing-" + std::to_string( ::getpid() ) + "-" + std::to_string( seed ) );
    static bool cleanup = false;
    if ( !cleanup )
    {
      cleanup = true;
      std::atexit( [] {
        for ( const auto &[s, run] : runs )
        {
          std::error_code ec;
          std::filesystem::remove_all( run.dir, ec );
        }
      } );
    }
    return runs.emplace( seed, simulateRun( o, dir ) ).first->second;
  }

  //! The run every tracing test shares; GEOSTATION_TRACING_SEED simulates a fresh one (another scene, noise and pose errors).
  inline const HighwayRun &highwayRun()
  {
    const char *seed = std::getenv( "GEOSTATION_TRACING_SEED" );
    return highwayRun( seed ? static_cast<uint32_t>( std::strtoul( seed, nullptr, 10 ) ) : 7 );
  }

  //! Where an operator clicks: on the truth line (a dash of a dashed one) about `rangeM` ahead of the camera, projected by the true orientation.
  inline TraceSeed seedOn( const HighwayRun &run, const std::string &prefix, const std::string &imageId, double rangeM, const Eigen::Vector2d &clickError )
  {
    const OrientedImage image = run.truth.orientedImage( run.truth.image( imageId ) );
    const Eigen::Vector3d c = image.exterior().projectionCentre;
    for ( const TruthRoadLine &part : run.roads )
    {
      if ( part.id.rfind( prefix + "-", 0 ) != 0 )
        continue;
      const std::vector<Eigen::Vector3d> &line = part.vertices;
      for ( size_t i = 0; i + 1 < line.size(); ++i )
        for ( int k = 0; k < 20; ++k )
        {
          const Eigen::Vector3d p = line[i] + k / 20.0 * ( line[i + 1] - line[i] );
          const GroundProjection g = image.projectGroundToPixel( p );
          if ( g.ok() && g.inFrame && ( p - c ).head<2>().norm() >= rangeM && ( i > 0 || k > 4 ) && ( i + 2 < line.size() || k < 15 ) )
            return TraceSeed { "seed", imageId, g.pixelInImage + clickError, std::nullopt };
        }
    }
    throw std::runtime_error( "the line is not in view of " + imageId );
  }

  struct LineScore
  {
    BufferScore buffer;
    double rms15 = 0.0;        //!< 3-D distance to the truth line, vertices within 15 m of the camera
    double normalisedSd = 0.0; //!< of cross-line and height errors over their sigmas
    double lengthM = 0.0;
    int vertices = 0, near = 0;
  };

  inline LineScore score( const RoadTraceSummary &s, const std::vector<Eigen::Vector3d> &truth, const HighwayRun &run, double bufferM )
  {
    LineScore out;
    std::vector<Eigen::Vector3d> traced;
    for ( const TracedVertex &v : s.vertices )
      traced.push_back( v.point );
    out.vertices = static_cast<int>( traced.size() );
    if ( traced.size() < 2 )
      return out;
    // the truth from the first vertex to the reach of the last station (its camera + 12 m along the line)
    const double from = projectOnto( truth, traced.front(), true ).station;
    const Eigen::Vector3d lastCamera = run.block.image( s.stations.back().referenceImageId ).exterior->projectionCentre;
    const double to = std::max( projectOnto( truth, lastCamera, true ).station + 12.0, projectOnto( truth, traced.back(), true ).station );
    out.buffer = bufferScore( traced, polylineBetween( truth, from, to ), bufferM );
    double sum = 0.0, sumN = 0.0, sumN2 = 0.0;
    int n = 0;
    for ( const TracedVertex &v : s.vertices )
    {
      const PolylineProjection p = projectOnto( truth, v.point, false );
      if ( v.rangeM <= 15.0 )
      {
        sum += p.distance * p.distance;
        ++out.near;
      }
      // cross-line (horizontal) and height errors against their sigmas
      const Eigen::Vector3d e = v.point - p.point;
      const Eigen::Vector3d across = Eigen::Vector3d( -p.tangent.y(), p.tangent.x(), 0.0 ).normalized();
      for ( const Eigen::Vector3d &axis : { across, Eigen::Vector3d( Eigen::Vector3d::UnitZ() ) } )
      {
        const double z = e.dot( axis ) / std::sqrt( axis.dot( v.covariance * axis ) );
        sumN += z;
        sumN2 += z * z;
        ++n;
      }
    }
    out.rms15 = out.near ? std::sqrt( sum / out.near ) : 0.0;
    out.normalisedSd = n > 1 ? std::sqrt( ( sumN2 - sumN * sumN / n ) / ( n - 1 ) ) : 0.0;
    out.lengthM = s.lengthM;
    return out;
  }

  struct HighwayLine
  {
    const char *name, *prefix;
    double minCompleteness, minCorrectness; // asserted on the runs with GNSS/INS errors
    double maxRms15;                        // m, likewise
  };
  // the truth's "edge" is the asphalt / kerb face, "kerb" the kerb's outer edge to the verge.
  // RMS within 15 m measured on five runs (seeds 7, 11, 23, 31, 47): centre 2.1-2.8 cm, lane 2.3-3.3 cm,
  // edge line 2.1-2.6 cm, kerb face 2.0-2.4 cm. The dashed lane line misses the 3 cm target on one of the
  // five (seed 11, 3.3 cm): the trajectory's height error, the same at every line (station by station the
  // lane's and the centre line's mean height errors agree within 1 cm, drifting +4 to -5 cm along the run),
  // which the dash's fewer vertices sample where it is largest; the sigmas carry it (normalised sd 1.01).
  inline const HighwayLine kHighwayLines[] = {
    { "centre (solid)", "R1-centre1", 0.95, 0.98, 0.030 },
    { "lane (dashed)", "R1-separator3", 0.90, 0.97, 0.035 },
    { "edge line", "R1-edge_line5", 0.95, 0.98, 0.030 },
    { "kerb face", "R1-edge-right", 0.95, 0.98, 0.030 },
  };
  // the kerb's outer edge to the gravel shoulder: weak contrast, and the shoulder's edge to the verge 1.5 m
  // further out has the same polarity. Measured on five runs (seeds 7, 11, 23, 31, 47), the whole run from one
  // click on each: 0.99-1.00 / 1.00, RMS within 15 m 2.5-3.0 cm, normalised sd 0.86-1.01
  inline const HighwayLine kKerbOuterEdge { "kerb outer edge", "R1-kerb-right", 0.95, 0.97, 0.035 };

  inline RoadTraceSummary traceFromSeed( const HighwayRun &run, const Block &block, const std::string &prefix, const std::string &imageId, TraceMethod method, int maxStations = 0,
                                  int stationsBehind = RoadTraceOptions().stationsBehind )
  {
    const TraceSeed seed = seedOn( run, prefix, imageId, 8.0, Eigen::Vector2d( 1.2, -0.8 ) );
    RoadTraceOptions options;
    options.method = method;
    options.maxStations = maxStations;
    options.stationsBehind = stationsBehind;
    return traceRoadLine( block, seed, options, fileGreyImageSource( block ) );
  }

  /**
   * With GEOSTATION_TRACING_DUMP=dir set, writes a traced line's vertices
   * with their errors against the truth (across the line and in height, m),
   * their sigmas, range and image count to dir/<name>.csv, and whether the
   * vertex lies on a painted part of the truth line (a dash) or between.
   */
  inline void dumpVertices( const std::string &name, const RoadTraceSummary &s, const HighwayRun &run, const std::string &prefix )
  {
    const char *dir = std::getenv( "GEOSTATION_TRACING_DUMP" );
    if ( !dir )
      return;
    const std::vector<Eigen::Vector3d> truth = joinedTruthLine( run.roads, prefix );
    std::string file = name;
    for ( char &ch : file )
      if ( !std::isalnum( static_cast<unsigned char>( ch ) ) )
        ch = '_';
    FILE *f = std::fopen( ( std::filesystem::path( dir ) / ( file + ".csv" ) ).c_str(), "w" );
    if ( !f )
      return;
    std::fprintf( f, "station_m,range_m,images,across_m,height_m,sigma_across_m,sigma_height_m,on_paint,station_id\n" );
    for ( const TracedVertex &v : s.vertices )
    {
      const PolylineProjection p = projectOnto( truth, v.point, false );
      const Eigen::Vector3d e = v.point - p.point;
      const Eigen::Vector3d across = Eigen::Vector3d( -p.tangent.y(), p.tangent.x(), 0.0 ).normalized();
      double toPaint = std::numeric_limits<double>::infinity();
      for ( const TruthRoadLine &part : run.roads )
        if ( part.id.rfind( prefix + "-", 0 ) == 0 && part.vertices.size() >= 2 )
        {
          const PolylineProjection q = projectOnto( part.vertices, v.point, true );
          const double a = projectOnto( part.vertices, part.vertices.front(), true ).station, b = projectOnto( part.vertices, part.vertices.back(), true ).station;
          if ( q.station > a + 1e-6 && q.station < b - 1e-6 )
            toPaint = std::min( toPaint, q.distance );
        }
      std::fprintf( f, "%.3f,%.2f,%zu,%.4f,%.4f,%.4f,%.4f,%d,%s\n", p.station, v.rangeM, v.imageIds.size(), e.dot( across ), e.z(),
                    std::sqrt( across.dot( v.covariance * across ) ), std::sqrt( v.covariance( 2, 2 ) ), toPaint < 0.3 ? 1 : 0, v.stationId.c_str() );
    }
    std::fclose( f );
    if ( FILE *g = std::fopen( ( std::filesystem::path( dir ) / ( file + "-stations.csv" ) ).c_str(), "w" ) )
    {
      std::fprintf( g, "station_id,method,pixels,bridged_gaps,vertices,stop\n" );
      for ( const TracedStation &t : s.stations )
        std::fprintf( g, "%s,%s,%d,%d,%d,%s\n", t.stationId.c_str(), traceMethodName( t.method ).c_str(), t.pixelsFollowed, t.bridgedGaps, t.vertices, traceStopName( t.stop ).c_str() );
      std::fclose( g );
    }
  }

  inline void print( const std::string &name, const RoadTraceSummary &s, const LineScore &sc )
  {
    std::printf( "%-16s %-28s stations %2zu vertices %3d length %6.1f m  completeness %.3f correctness %.3f  RMS(<=15 m) %.3f m (%d)  normalised sd %.2f  "
                 "multi-station %d vertices, %d rays (%d not used, %d unconfirmed), sigma0 %.2f%s  stop %s: %s\n",
                 name.c_str(), s.methods().c_str(), s.stations.size(), sc.vertices, sc.lengthM, sc.buffer.completeness, sc.buffer.correctness, sc.rms15, sc.near,
                 sc.normalisedSd, s.multiStation.vertices, s.multiStation.observations, s.multiStation.rejected, s.multiStation.unconfirmed, s.sigma0, s.sigmaScaled ? " (applied)" : "", traceStopName( s.stop ).c_str(), s.message.c_str() );
  }
}

#endif // GEOSTATION_TESTS_HIGHWAYTRACING_H

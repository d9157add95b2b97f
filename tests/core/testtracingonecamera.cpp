/***************************************************************************
  testtracingonecamera.cpp - road tracing where a station's two images
  share one camera model
  -------------------------------------------------------------------------
  A forward pair whose cameras are one calibrated model (COLMAP's
  single_camera, a rig of identical cameras) has one camera entry for both
  images of every station. The reference and the stereo partner are then
  told apart by where they sit in the rig (tracing/rigroles.h), not by their
  camera entry: the same lines are traced in 3-D as with a camera entry per
  camera. Once a partner looked up by camera id was the reference image
  itself, and every seed ran to the end of the run with nothing in 3-D.
  The same run is also traced as COLMAP hands it over with one camera
  model: images in a folder per camera, one file name per instant.
 ***************************************************************************/
#include <algorithm>
#include <filesystem>
#include <unistd.h>

#include <gtest/gtest.h>

#include "highwaytracing.h"
#include "io/blockexport.h"
#include "io/colmapimport.h"
#include "io/colmapmodel.h"
#include "tracing/rigroles.h"

using namespace geostation;
using namespace geostation::highwaytracing;

namespace
{
  //! A 12-station highway run of a van whose two forward cameras are one model (seed 7, as the tracing tests' run).
  const HighwayRun &oneModelRun()
  {
    static const HighwayRun run = []
    {
      SimulationOptions o;
      o.stations = 12;
      o.stationSpacingM = 10.0;
      o.cameras = 2;
      o.oneCameraModel = true;
      o.imageWidth = 1024;
      o.imageHeight = 768;
      o.seed = 7;
      o.degradation.noiseSigma = 2.0;
      o.degradation.blurSigmaPx = 0.6;
      o.degradation.jpegQuality = 85;
      o.poseNoiseScale = 0.2;
      const std::filesystem::path dir = std::filesystem::temp_directory_path() / ( "geostation-onecamera-" + std::to_string( ::getpid() ) );
      HighwayRun r = simulateRun( o, dir );
      std::atexit( [] { std::error_code ec; std::filesystem::remove_all( std::filesystem::temp_directory_path() / ( "geostation-onecamera-" + std::to_string( ::getpid() ) ), ec ); } );
      return r;
    }();
    return run;
  }
}

TEST( TracingOneCameraModel, BothImagesOfAStationShareTheCameraEntry )
{
  const HighwayRun &run = oneModelRun();
  ASSERT_EQ( run.block.cameras.size(), 1u );
  EXPECT_EQ( run.block.image( "S0003_FL" ).cameraId, run.block.image( "S0003_FR" ).cameraId );
}

TEST( TracingOneCameraModel, TheRigTellsLeftFromRight )
{
  const HighwayRun &run = oneModelRun();
  const Block &b = run.block;
  // the seed pair's relation found again at another station, the right image beside the left
  const RigRelation seedPair = rigRelation( b.image( "S0001_FL" ), b.image( "S0001_FR" ) );
  EXPECT_NEAR( seedPair.offset.norm(), 2.0, 0.1 ); // the mounts are 2 m apart
  const StationSequence sequence( b );
  const int seedStation = sequence.indexOf( "S0001" );
  const BlockImage *partner = imageInRelation( b, sequence.at( sequence.indexOf( "S0009" ) ), b.image( "S0009_FL" ), seedPair, "van" );
  ASSERT_NE( partner, nullptr );
  EXPECT_EQ( partner->id, "S0009_FR" );
  EXPECT_LT( rigRelationCost( rigRelation( b.image( "S0009_FL" ), b.image( "S0009_FR" ) ), seedPair ), 0.2 );
  EXPECT_GT( rigRelationCost( rigRelation( b.image( "S0009_FR" ), b.image( "S0009_FL" ) ), seedPair ), 1.5 );
  // the left image's part through the whole run, from either image as the seed
  for ( const std::string suffix : { "_FL", "_FR" } )
  {
    const std::vector<const BlockImage *> role = imagesInRole( b, sequence, seedStation, b.image( "S0001" + suffix ) );
    ASSERT_EQ( role.size(), static_cast<size_t>( sequence.size() ) );
    for ( int k = 0; k < sequence.size(); ++k )
    {
      ASSERT_NE( role[k], nullptr ) << sequence.at( k ).id;
      EXPECT_EQ( role[k]->id, sequence.at( k ).id + suffix );
    }
  }
}

TEST( TracingOneCameraModel, LinesTracedIn3DThroughTheRun )
{
  const HighwayRun &run = oneModelRun();
  for ( const HighwayLine &c : { kHighwayLines[0], kHighwayLines[3] } )
  {
    SCOPED_TRACE( c.name );
    const std::vector<Eigen::Vector3d> truth = joinedTruthLine( run.roads, c.prefix );
    const RoadTraceSummary s = traceFromSeed( run, run.block, c.prefix, "S0001_FL", TraceMethod::Auto );
    const LineScore sc = score( s, truth, run, 0.10 );
    print( c.name, s, sc );
    EXPECT_TRUE( s.ok() ) << s.message;
    EXPECT_EQ( s.stop, TraceStop::EndOfRun ) << s.message;
    EXPECT_GE( s.lengthM, 100.0 );
    EXPECT_GE( sc.buffer.completeness, c.minCompleteness );
    EXPECT_GE( sc.buffer.correctness, c.minCorrectness );
    EXPECT_LE( sc.rms15, c.maxRms15 );
    for ( const TracedStation &station : s.stations )
    {
      EXPECT_EQ( station.referenceImageId, station.stationId + "_FL" );
      EXPECT_EQ( station.partnerImageId, station.stationId + "_FR" );
    }
  }
}

TEST( TracingOneCameraModel, AStationWithoutThePartnerSaysSo )
{
  // the right image of the fifth station lost: tracing stops there and names what is missing, the line so far kept
  const HighwayRun &run = oneModelRun();
  Block block = run.block;
  block.images.erase( std::find_if( block.images.begin(), block.images.end(), []( const BlockImage &i ) { return i.id == "S0005_FR"; } ) );
  const RoadTraceSummary s = traceFromSeed( run, block, kHighwayLines[0].prefix, "S0001_FL", TraceMethod::Auto );
  EXPECT_EQ( s.stop, TraceStop::NoStereoPartner ) << s.message;
  EXPECT_NE( s.message.find( "station S0005 has no oriented image placed beside S0005_FL as the stereo partner S0001_FR is beside S0001_FL" ), std::string::npos ) << s.message;
  EXPECT_GE( s.lengthM, 30.0 );
}

TEST( TracingOneCameraModel, APartnerThatNeverMatchesSaysSo )
{
  // the right images' orientation 4 degrees off: the line is followed in the left images, but no vertex is found in
  // the right ones; the stop says so, not "traced to the end of the run"
  const HighwayRun &run = oneModelRun();
  Block block = run.block;
  for ( BlockImage &image : block.images )
    if ( image.id.size() > 3 && image.id.substr( image.id.size() - 3 ) == "_FR" )
      image.exterior->kappaDeg += 4.0;
  const RoadTraceSummary s = traceFromSeed( run, block, kHighwayLines[0].prefix, "S0001_FL", TraceMethod::Auto );
  EXPECT_FALSE( s.ok() );
  EXPECT_EQ( s.stop, TraceStop::NoStereoPartner ) << traceStopName( s.stop );
  EXPECT_NE( s.message.find( "followed in the images through 12 station(s), but no vertex of it was found in the stereo partner (at station S0001: " ),
             std::string::npos ) << s.message;
  EXPECT_EQ( s.message.find( "traced to the end of the run" ), std::string::npos ) << s.message;
}

TEST( TracingOneCameraModel, FromACOLMAPSingleCameraModel )
{
  // the run as a COLMAP model of one camera, its images named by COLMAP's rig convention (FL/S0001.tif,
  // FR/S0001.tif) and no frames: imported, its stations come from the names, and the lines are traced
  const HighwayRun &run = oneModelRun();
  namespace fs = std::filesystem;
  ColmapModel model = colmapModelFromBlock( run.block, {}, {}, nullptr );
  ASSERT_EQ( model.cameras.size(), 1u );
  ASSERT_TRUE( model.frames.empty() );
  const fs::path dir = run.dir / "colmap-single-camera";
  for ( ColmapImage &image : model.images )
  {
    const std::string stem = fs::path( image.name ).stem().string(); // S0001_FL
    image.name = stem.substr( 6 ) + "/" + stem.substr( 0, 5 ) + ".tif";
    fs::create_directories( dir / stem.substr( 6 ) );
    fs::copy_file( run.dir / "images" / ( stem + ".tif" ), dir / image.name, fs::copy_options::overwrite_existing );
  }
  model.writeText( dir / "sparse" );
  ColmapImportOptions options;
  options.crs = run.block.crs;
  options.imageFolder = dir;
  HighwayRun imported = run;
  const BlockImportSummary import = importColmapModel( ColmapModel::read( dir / "sparse" ), dir / "sparse", options );
  imported.block = import.block;
  ASSERT_EQ( imported.block.cameras.size(), 1u );
  ASSERT_EQ( imported.block.stations.size(), 12u );
  bool said = false;
  for ( const std::string &sentence : import.converted )
    said = said || sentence.find( "12 file name(s) found in more than one of the folders FL/, FR/ became exposure stations of up to 2 image(s)" ) != std::string::npos;
  EXPECT_TRUE( said );
  EXPECT_EQ( imported.block.image( "FR/S0004" ).stationId, imported.block.image( "FL/S0004" ).stationId );

  const HighwayLine &c = kHighwayLines[0];
  TraceSeed seed = seedOn( run, c.prefix, "S0001_FL", 8.0, Eigen::Vector2d( 1.2, -0.8 ) );
  seed.imageId = "FL/S0001";
  const RoadTraceSummary s = traceRoadLine( imported.block, seed, RoadTraceOptions(), fileGreyImageSource( imported.block ) );
  const LineScore sc = score( s, joinedTruthLine( run.roads, c.prefix ), imported, 0.10 );
  print( std::string( c.name ) + ", COLMAP", s, sc );
  EXPECT_EQ( s.stop, TraceStop::EndOfRun ) << s.message;
  EXPECT_GE( sc.buffer.completeness, c.minCompleteness );
  EXPECT_GE( sc.buffer.correctness, c.minCorrectness );
  // COLMAP gives no pose sigmas: the simulated trajectory's 2-3 cm pose errors are then unknown to the
  // multi-station step, which turns most rays of the stations behind away as too far off (3.8 cm here,
  // against 2.6 cm with the block's sigmas)
  EXPECT_LE( sc.rms15, 0.05 );
  ASSERT_FALSE( s.stations.empty() );
  EXPECT_EQ( s.stations.front().partnerImageId, "FR/S0001" );
}

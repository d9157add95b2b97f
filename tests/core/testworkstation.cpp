// The Multiview's core: the station sequence of a run, camera view cones,
// conjugate-point proposals and vertices against the simulator's truth
// (highway preset), and the image cache.
#include <cmath>
#include <atomic>
#include <filesystem>
#include <thread>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "io/block.h"
#include "simulation/surveysimulator.h"
#include "workstation/matchimagecache.h"
#include "workstation/pointmeasurer.h"
#include "io/stationsequence.h"
#include "workstation/viewcone.h"
#include "simulationtruth.h"
#include "texturedground.h"

using namespace geostation;

namespace
{
  //! A short highway run with exact orientations (the block is the truth), simulated once.
  const std::filesystem::path &highwayRun()
  {
    static std::filesystem::path dir;
    if ( dir.empty() )
    {
      dir = std::filesystem::temp_directory_path() / ( "geostation-ws-highway-" + std::to_string( ::getpid() ) );
      std::filesystem::remove_all( dir );
      SimulationOptions options;
      options.preset = SurveyPreset::Highway;
      options.seed = 7;
      options.outputDir = dir;
      options.stations = 10;
      options.degradation.noiseSigma = 1.0;
      simulateSurvey( options );
    }
    return dir;
  }

  bool insideRing( const std::vector<Eigen::Vector2d> &ring, const Eigen::Vector2d &p )
  {
    bool inside = false;
    for ( size_t i = 0, j = ring.size() - 1; i < ring.size(); j = i++ )
      if ( ( ring[i].y() > p.y() ) != ( ring[j].y() > p.y() )
           && p.x() < ( ring[j].x() - ring[i].x() ) * ( p.y() - ring[i].y() ) / ( ring[j].y() - ring[i].y() ) + ring[i].x() )
        inside = !inside;
    return inside;
  }
}

TEST( StationSequence, RunOrderNavigationAndPicking )
{
  const Block block = Block::load( highwayRun() / "truth.geostation.json" );
  const StationSequence run( block );
  ASSERT_EQ( run.size(), 10 );
  for ( int i = 0; i < run.size(); ++i )
  {
    EXPECT_EQ( run.at( i ).imageIds.size(), 3u );
    ASSERT_TRUE( run.at( i ).position.has_value() );
    if ( i > 0 )
    {
      EXPECT_LT( run.at( i - 1 ).time, run.at( i ).time );
    }
    // picking a station on the map: a point 1 m beside it finds it
    EXPECT_EQ( run.indexNearest( run.at( i ).position->head<2>() + Eigen::Vector2d( 0.7, 0.7 ) ), i );
    EXPECT_EQ( run.indexNearestTime( run.at( i ).time ), i );
  }
  EXPECT_EQ( run.stepped( 0, -1 ), 0 );
  EXPECT_EQ( run.stepped( 2, 10 ), 9 );
  EXPECT_EQ( run.stepped( 2, 1 ), 3 );
  EXPECT_EQ( run.indexOf( run.at( 4 ).id ), 4 );
  EXPECT_EQ( run.indexOf( "nope" ), -1 );
  EXPECT_EQ( run.indexNearestTime( "not a time" ), -1 );
  const double t0 = *StationSequence::secondsFromIsoTime( "2025-05-01T10:00:00.000Z" );
  EXPECT_NEAR( *StationSequence::secondsFromIsoTime( "2025-05-01T10:00:01.250Z" ) - t0, 1.25, 1e-9 );
  EXPECT_NEAR( t0, 1746093600.0, 1e-6 );

  // an image without a station is a station of its own
  Block loose = block;
  loose.images[0].stationId.clear();
  const StationSequence looseRun( loose );
  EXPECT_EQ( looseRun.size(), 11 );
  EXPECT_GE( looseRun.indexOf( loose.images[0].id ), 0 );
}

TEST( ViewCone, HoldsWhatTheCameraSeesAndNothingBehindIt )
{
  const Block block = Block::load( highwayRun() / "truth.geostation.json" );
  const TruthTable truth = readTruth( highwayRun() / "truth.gpkg" );
  int seen = 0, behind = 0;
  for ( const BlockImage &image : block.images )
  {
    const OrientedImage oriented = block.orientedImage( image );
    ViewConeOptions options;
    options.groundHeightM = oriented.exterior().projectionCentre.z() - 2.6;
    options.maxRangeM = 60.0;
    const std::vector<Eigen::Vector2d> cone = viewCone( oriented, options );
    ASSERT_GE( cone.size(), 3u ) << image.id;
    for ( const auto &[id, point] : truth.objects )
    {
      const bool inImage = truth.imageTruth.count( { id, image.id } ) > 0;
      const double range = ( point.head<2>() - oriented.exterior().projectionCentre.head<2>() ).norm();
      if ( inImage && range < 55.0 )
      {
        EXPECT_TRUE( insideRing( cone, point.head<2>() ) ) << id << " in " << image.id;
        ++seen;
      }
      if ( oriented.cameraFromWorld( point ).z() > 0 )
      {
        EXPECT_FALSE( insideRing( cone, point.head<2>() ) ) << id << " behind " << image.id;
        ++behind;
      }
    }
  }
  EXPECT_GT( seen, 20 );
  EXPECT_GT( behind, 20 );
  EXPECT_THROW( viewCone( block.orientedImage( block.images[0] ), ViewConeOptions { 0, -1, 8 } ), std::invalid_argument );
}

TEST( PointMeasurer, ProposalsAndIntersectionAgreeWithTheTruth )
{
  const Block block = Block::load( highwayRun() / "truth.geostation.json" );
  const TruthTable truth = readTruth( highwayRun() / "truth.gpkg" );
  const StationSequence run( block );
  MatchImageCache cache;
  int tried = 0, matchedCount = 0, lsmCount = 0, proposedWithinPixel = 0, within3Sigma = 0, intersected = 0, shapedWithinPixel = 0;
  double sumSquaredErrorPx = 0;
  for ( const SequenceStation &station : run.stations() )
  {
    std::vector<OrientedImage> oriented;
    std::vector<std::shared_ptr<const MatchImage>> pixels;
    for ( const std::string &id : station.imageIds )
    {
      oriented.push_back( block.orientedImage( block.image( id ) ) );
      pixels.push_back( cache.get( block.imageFilePath( block.image( id ) ).string() ).image );
      ASSERT_TRUE( pixels.back() );
    }
    std::vector<MeasurementView> views;
    for ( size_t i = 0; i < oriented.size(); ++i )
      views.push_back( MeasurementView { station.imageIds[i], &oriented[i], pixels[i].get() } );
    for ( const auto &[id, point] : truth.objects )
    {
      // clicked at its true pixel in the front-left image, seen in front-right too
      const auto left = truth.imageTruth.find( { id, station.imageIds[0] } );
      const auto right = truth.imageTruth.find( { id, station.imageIds[1] } );
      if ( left == truth.imageTruth.end() || right == truth.imageTruth.end() )
        continue;
      // objects with an outline at their truth point (a lid's centre or a sign panel is featureless)
      if ( id.rfind( "pole_", 0 ) != 0 && id.rfind( "hydrant_", 0 ) != 0 )
        continue;
      if ( ( point - oriented[0].exterior().projectionCentre ).norm() > 40.0 )
        continue;
      ++tried;
      const std::vector<ConjugateProposal> proposals = proposeConjugates( views, 0, left->second );
      ASSERT_EQ( proposals.size(), 3u );
      // with the window's shape predicted from the road plane (as the Multiview does): a pole's foot is on the
      // road, its shaft above it; the square window competes and the proposal stays right
      ProposalOptions onRoad;
      const double roadZ = oriented[0].exterior().projectionCentre.z() - 2.65;
      onRoad.groundOfPixel = [roadZ]( const OrientedImage &image, const Eigen::Vector2d &pixel ) { return roadPlanePoint( image, pixel, roadZ ); };
      const ConjugateProposal shaped = proposeConjugates( views, 0, left->second, onRoad )[1];
      shapedWithinPixel += shaped.matched() && ( shaped.pixelInImage - right->second ).norm() < 1.0;
      EXPECT_TRUE( !shaped.matched() || ( shaped.pixelInImage - right->second ).norm() < 2.0 ) << id;
      EXPECT_TRUE( proposals[1].curveInFrame );
      // the true conjugate lies on the epipolar curve (the orientation is exact)
      EXPECT_LT( proposals[1].curve.distanceToCurvePx( right->second ), 0.05 ) << id;
      const double errorPx = ( proposals[1].pixelInImage - right->second ).norm();
      if ( std::getenv( "GEOSTATION_DEBUG" ) )
        std::cout << id << " " << station.id << " matched " << proposals[1].matched() << " score " << proposals[1].score << " err " << errorPx << " reason " << proposals[1].message
                  << " third " << proposals[2].matched() << " " << proposals[2].curveInFrame << " range " << ( point - oriented[0].exterior().projectionCentre ).norm() << "\n";
      // every proposal says what it is (docs/conventions.md §8), and a failed one why
      for ( size_t i = 1; i < proposals.size(); ++i )
        if ( !proposals[i].matched() )
        {
          EXPECT_FALSE( proposals[i].message.empty() ) << matchStatusName( proposals[i].status );
        }
      if ( !proposals[1].matched() )
        continue;
      ++matchedCount;
      lsmCount += proposals[1].status == MatchStatus::Lsm;
      sumSquaredErrorPx += errorPx * errorPx;
      proposedWithinPixel += errorPx < 1.0 ? 1 : 0;
      std::vector<VertexObservation> observations { { station.imageIds[0], &oriented[0], left->second, 0.5 } };
      for ( size_t i = 1; i < proposals.size(); ++i )
        if ( proposals[i].matched() )
          observations.push_back( { station.imageIds[i], &oriented[i], proposals[i].pixelInImage, 0.5 } );
      const MeasuredVertex v = intersectVertex( observations );
      ASSERT_TRUE( v.ok() ) << v.message;
      ++intersected;
      EXPECT_EQ( v.method, VertexMethod::Intersection );
      EXPECT_EQ( v.imageIds.size(), observations.size() );
      EXPECT_GT( v.maxRayAngleDeg, 0.5 );
      const Eigen::Vector3d error = v.point - point;
      if ( std::abs( error.x() ) < 3 * v.sigmaM.x() + 0.01 && std::abs( error.y() ) < 3 * v.sigmaM.y() + 0.01 && std::abs( error.z() ) < 3 * v.sigmaM.z() + 0.01 )
        ++within3Sigma;
    }
  }
  std::cout << "pole feet: " << tried << " clicked, " << matchedCount << " matched, " << proposedWithinPixel << " proposals within 1 px (RMS "
            << std::sqrt( sumSquaredErrorPx / std::max( 1, matchedCount ) ) << " px), " << within3Sigma << " of " << intersected
            << " intersections within 3 sigma\n";
  std::cout << "with the road plane's window shapes: " << shapedWithinPixel << " proposals within 1 px\n";
  ASSERT_GE( tried, 6 );
  EXPECT_GE( proposedWithinPixel, 0.8 * tried ) << proposedWithinPixel << " of " << tried;
  EXPECT_GE( shapedWithinPixel, 0.8 * tried ) << shapedWithinPixel << " of " << tried;
  EXPECT_GE( lsmCount, 0.8 * matchedCount ) << "least squares confirms the proposals on these images";
  EXPECT_GE( within3Sigma, 0.8 * intersected ) << within3Sigma << " of " << intersected;
}

TEST( PointMeasurer, ThirdRayFlagsProposalsAtAnotherDepth )
{
  // three forward cameras 1 m apart across a van, and a point 15 m ahead on the road; one proposal is
  // then moved along the reference pixel's epipolar curve (the point at another depth), where the
  // epipolar check cannot see it: the third ray does
  const Camera camera = texturedground::frameCamera( 1024, 768, 900.0 );
  std::vector<OrientedImage> oriented;
  for ( const double x : { -1.0, 0.0, 1.0 } )
    oriented.push_back( texturedground::lookingAt( camera, Eigen::Vector3d( x, 0.0, 2.5 ), 0.0, 10.0 ) );
  std::vector<MeasurementView> views;
  for ( size_t i = 0; i < 3; ++i )
    views.push_back( MeasurementView { "view" + std::to_string( i ), &oriented[i], nullptr } );
  const Eigen::Vector3d point( 0.3, 15.0, 0.0 );
  std::vector<ConjugateProposal> proposals( 3 );
  for ( size_t i = 1; i < 3; ++i )
  {
    ASSERT_TRUE( oriented[i].projectGroundToPixel( point ).inFrame );
    proposals[i].status = MatchStatus::Lsm;
    proposals[i].sigmaPx = 0.1;
    proposals[i].pixelInImage = oriented[i].projectGroundToPixel( point ).pixelInImage;
  }
  const Eigen::Vector2d reference = oriented[0].projectGroundToPixel( point ).pixelInImage;
  ProposalOptions options;
  std::vector<ConjugateProposal> right = proposals;
  flagInconsistentProposals( views, 0, reference, options, right );
  EXPECT_TRUE( right[1].matched() && right[2].matched() );
  // the same pixel at another depth, in view 2: on its epipolar curve, but not where view 1 says
  const Eigen::Vector3d deeper = point + 0.3 * ( point - oriented[0].exterior().projectionCentre );
  std::vector<ConjugateProposal> wrong = proposals;
  wrong[2].pixelInImage = oriented[2].projectGroundToPixel( deeper ).pixelInImage;
  ASSERT_GT( ( wrong[2].pixelInImage - proposals[2].pixelInImage ).norm(), 3.0 );
  flagInconsistentProposals( views, 0, reference, options, wrong );
  // with three rays the two proposals contradict each other, and either may be the wrong one: neither is taken
  EXPECT_FALSE( wrong[1].matched() );
  EXPECT_FALSE( wrong[2].matched() );
  EXPECT_EQ( wrong[2].status, MatchStatus::Inconsistent );
  EXPECT_NE( wrong[2].message.find( "disagree" ), std::string::npos ) << wrong[2].message;
  // a fourth view that agrees with view 1 singles out the wrong one
  oriented.push_back( texturedground::lookingAt( camera, Eigen::Vector3d( 0.5, -3.0, 2.5 ), 0.0, 10.0 ) );
  views.clear();
  for ( size_t i = 0; i < 4; ++i )
    views.push_back( MeasurementView { "view" + std::to_string( i ), &oriented[i], nullptr } );
  std::vector<ConjugateProposal> four = proposals;
  four[2] = wrong[2];
  four[2].status = MatchStatus::Lsm;
  four.push_back( proposals[1] );
  four[3].pixelInImage = oriented[3].projectGroundToPixel( point ).pixelInImage;
  flagInconsistentProposals( views, 0, reference, options, four );
  EXPECT_TRUE( four[1].matched() );
  EXPECT_FALSE( four[2].matched() );
  EXPECT_TRUE( four[3].matched() );
  // two rays only: nothing to compare (the epipolar check is the test there)
  std::vector<ConjugateProposal> pair = { proposals[0], proposals[1], wrong[2] };
  pair[1].status = MatchStatus::NoPeak;
  pair[2].status = MatchStatus::Lsm;
  views.resize( 3 );
  flagInconsistentProposals( views, 0, reference, options, pair );
  EXPECT_TRUE( pair[2].matched() );
}

TEST( PointMeasurer, SingleRayVerticesOnTheRoadPlane )
{
  const Block block = Block::load( highwayRun() / "truth.geostation.json" );
  const TruthTable truth = readTruth( highwayRun() / "truth.gpkg" );
  const BlockImage &image = block.images[0];
  const OrientedImage oriented = block.orientedImage( image );
  int n = 0;
  for ( const auto &[id, point] : truth.objects )
  {
    const auto pixel = truth.imageTruth.find( { id, image.id } );
    if ( pixel == truth.imageTruth.end() )
      continue;
    const MeasuredVertex v = roadPlaneVertex( VertexObservation { image.id, &oriented, pixel->second, 0.5 }, point.z(), 0.05 );
    ASSERT_TRUE( v.ok() ) << v.message;
    EXPECT_EQ( vertexMethodName( v.method ), "road-plane" );
    EXPECT_LT( ( v.point - point ).norm(), 1e-3 ) << id; // the plane through the point gives the point
    EXPECT_GT( v.sigmaM.z(), 0.04 );
    ++n;
  }
  EXPECT_GT( n, 2 );
  // a plane above the camera is behind it for a ray pointing down
  const MeasuredVertex sky = roadPlaneVertex( VertexObservation { image.id, &oriented, { 320, 470 }, 0.5 }, oriented.exterior().projectionCentre.z() + 5, 0.0 );
  EXPECT_FALSE( sky.ok() );
  EXPECT_FALSE( sky.message.empty() );
}

TEST( MatchImageCache, ReadsOnceForgetsTheOldestWithinItsBudgetAndRetriesAFilePutBack )
{
  const Block block = Block::load( highwayRun() / "truth.geostation.json" );
  MatchImageCache cache( 2 );
  const std::string a = block.imageFilePath( block.images[0] ).string(), b = block.imageFilePath( block.images[1] ).string(),
                    c = block.imageFilePath( block.images[2] ).string();
  const auto first = cache.get( a ).image;
  ASSERT_TRUE( first );
  EXPECT_EQ( first->width(), block.cameraOf( block.images[0] ).width );
  EXPECT_EQ( cache.get( a ).image.get(), first.get() );
  cache.get( b );
  cache.get( c );
  EXPECT_FALSE( cache.contains( a ) );
  EXPECT_TRUE( cache.contains( c ) );
  const MatchImageCache::Entry missing = cache.get( "/nonexistent/image.tif" );
  EXPECT_FALSE( missing.image );
  EXPECT_EQ( missing.status, MatchImageCache::Entry::Status::Unreadable );
  EXPECT_NE( missing.message.find( "/nonexistent/image.tif" ), std::string::npos ) << missing.message;

  // a memory budget of two and a half images: the third evicts the first, the most recent always stays
  const size_t imageBytes = first->bytes();
  EXPECT_EQ( imageBytes, static_cast<size_t>( first->width() ) * first->height() * 9 );
  MatchImageCache budget( 10, imageBytes * 5 / 2 );
  budget.get( a );
  budget.get( b );
  EXPECT_EQ( budget.bytes(), 2 * imageBytes );
  budget.get( c );
  EXPECT_FALSE( budget.contains( a ) );
  EXPECT_TRUE( budget.contains( b ) && budget.contains( c ) );
  EXPECT_EQ( budget.bytes(), 2 * imageBytes );
  MatchImageCache tiny( 10, imageBytes / 2 ); // an image larger than the budget: kept alone
  tiny.get( a );
  EXPECT_TRUE( tiny.contains( a ) );
  tiny.get( b );
  EXPECT_FALSE( tiny.contains( a ) );
  EXPECT_EQ( tiny.bytes(), imageBytes );

  // an image deleted while in use and put back: its error is remembered only while the file stays away
  const std::filesystem::path back = std::filesystem::temp_directory_path() / "geostation-cache-putback.tif";
  std::filesystem::remove( back );
  EXPECT_FALSE( cache.get( back.string() ).image );
  EXPECT_FALSE( cache.get( back.string() ).image );
  std::filesystem::copy_file( a, back );
  const MatchImageCache::Entry putBack = cache.get( back.string() );
  ASSERT_TRUE( putBack.image ) << putBack.message;
  EXPECT_EQ( putBack.image->width(), first->width() );
  std::filesystem::remove( back );
}

TEST( MatchImageCache, ThreadsShareLoadsWithinTheBudget )
{
  // the Multiview prefetches a station's images on worker threads while the operator's click reads them:
  // four threads asking for three images (and a missing one) over and over, with a budget of two images
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "geostation-cache-threads";
  std::filesystem::create_directories( dir );
  std::vector<std::string> paths;
  for ( int i = 0; i < 3; ++i )
  {
    cv::Mat pixels( 120, 160, CV_8UC1 );
    cv::randu( pixels, 0, 255 );
    paths.push_back( ( dir / ( "image" + std::to_string( i ) + ".png" ) ).string() );
    ASSERT_TRUE( cv::imwrite( paths.back(), pixels ) );
  }
  const size_t imageBytes = size_t( 160 ) * 120 * 9;
  MatchImageCache cache( 18, 2 * imageBytes );
  std::atomic<int> wrong { 0 };
  std::vector<std::thread> threads;
  for ( int t = 0; t < 4; ++t )
    threads.emplace_back( [&, t] {
      for ( int k = 0; k < 60; ++k )
      {
        const MatchImageCache::Entry e = cache.get( paths[( t + k ) % 3] );
        if ( !e.image || e.image->width() != 160 || e.image->bytes() != imageBytes )
          ++wrong;
        if ( k % 20 == 0 && cache.get( ( dir / "missing.png" ).string() ).image )
          ++wrong;
        if ( cache.bytes() > 2 * imageBytes )
          ++wrong;
      }
    } );
  for ( std::thread &thread : threads )
    thread.join();
  EXPECT_EQ( wrong.load(), 0 );
  EXPECT_LE( cache.bytes(), 2 * imageBytes );
  std::filesystem::remove_all( dir );
}

TEST( MatchImageCache, ThreadsAskingForWindowsOfLargeImagesGetTheirOwnPixels )
{
  // images too large to prepare whole are read a window at a time, one window kept per image: four threads
  // asking for different windows of two such images at once each get a window holding theirs, with the file's
  // pixels (the window a thread holds stays valid while another replaces the one kept)
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / ( "geostation-cache-windows-" + std::to_string( ::getpid() ) );
  std::filesystem::create_directories( dir );
  std::vector<std::string> paths;
  std::vector<cv::Mat> truth;
  for ( int i = 0; i < 2; ++i )
  {
    cv::Mat pixels( 300, 400, CV_8UC1 );
    cv::randu( pixels, 0, 255 );
    paths.push_back( ( dir / ( "large" + std::to_string( i ) + ".png" ) ).string() );
    ASSERT_TRUE( cv::imwrite( paths.back(), pixels ) );
    truth.push_back( pixels );
  }
  MatchImageCache cache( 18, size_t( 1 ) << 30, 20'000 ); // 120 000 px: too large to prepare whole
  ASSERT_TRUE( cache.get( paths[0] ).needsWindow );
  const std::vector<cv::Rect> windows { { 10, 10, 100, 80 }, { 250, 40, 120, 90 }, { 150, 200, 90, 90 }, { 0, 150, 110, 100 }, { 280, 190, 110, 100 } };
  std::atomic<int> wrong { 0 }, asked { 0 };
  std::vector<std::thread> threads;
  for ( int t = 0; t < 4; ++t )
    threads.emplace_back( [&, t] {
      for ( int k = 0; k < 40; ++k )
      {
        const size_t image = ( t + k ) % 2;
        const cv::Rect &window = windows[( 3 * t + k ) % windows.size()];
        const MatchImageCache::Entry e = cache.get( paths[image], window );
        ++asked;
        if ( !e.image || !e.image->holds( window ) )
        {
          ++wrong;
          continue;
        }
        for ( const cv::Point &p : { window.tl(), window.br() - cv::Point( 1, 1 ), cv::Point( window.x + window.width / 2, window.y + window.height / 2 ) } )
          if ( e.image->valueAt( p.x, p.y ) != static_cast<float>( truth[image].at<uint8_t>( p ) ) )
            ++wrong;
      }
    } );
  for ( std::thread &thread : threads )
    thread.join();
  EXPECT_EQ( asked.load(), 160 );
  EXPECT_EQ( wrong.load(), 0 );
  std::filesystem::remove_all( dir );
}

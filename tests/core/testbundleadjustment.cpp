// Bundle adjustment of a simulated highway run against exact truth.
#include <functional>
#include <limits>
#include <random>

#include <gtest/gtest.h>

#include "adjustment/bundleadjustment.h"
#include "adjustment/intersection.h"
#include "vanrig.h"

using namespace geostation;

namespace
{
  struct SurveyRun
  {
    std::vector<Camera> cameras;
    std::vector<BundleImage> truth;
    std::vector<Eigen::Vector3d> points;
  };

  //! Stations every 5 m northwards, three cameras each (opencv, none, brown_photo).
  SurveyRun highwayRun( int stations, int pointCount, std::mt19937 &rng )
  {
    SurveyRun run;
    const DistortionModel models[3] = { DistortionModel::OpenCV, DistortionModel::None, DistortionModel::BrownPhoto };
    for ( DistortionModel m : models )
      run.cameras.push_back( vanrig::camera( m ) );
    for ( int s = 0; s < stations; ++s )
      for ( int k = 0; k < 3; ++k )
      {
        const Eigen::Vector3d centre( 500000.0 + ( k - 1 ) * 1.0, 4400000.0 + 5.0 * s, 102.5 );
        const Eigen::Vector3d target = centre + Eigen::Vector3d( ( k - 1 ) * 4.0, 30.0, -2.0 );
        run.truth.push_back( { "S" + std::to_string( s ) + "_" + std::to_string( k ), run.cameras[k].id, vanrig::lookAt( centre, target ) } );
      }
    std::uniform_real_distribution<double> x( -6.0, 6.0 ), y( 12.0, 5.0 * stations + 35.0 ), z( 100.0, 106.0 );
    for ( int i = 0; i < pointCount; ++i )
      run.points.emplace_back( 500000.0 + x( rng ), 4400000.0 + y( rng ), z( rng ) );
    return run;
  }

  std::vector<BundleObservation> observe( const SurveyRun &run, std::mt19937 &rng, double noisePx )
  {
    std::normal_distribution<double> noise( 0.0, 1.0 );
    std::vector<BundleObservation> out;
    for ( const BundleImage &image : run.truth )
    {
      const Camera &camera = *std::find_if( run.cameras.begin(), run.cameras.end(), [&]( const Camera & c ) { return c.id == image.cameraId; } );
      const OrientedImage oriented( camera, image.exterior );
      for ( size_t i = 0; i < run.points.size(); ++i )
      {
        const GroundProjection g = oriented.projectGroundToPixel( run.points[i] );
        if ( g.ok() && g.inFrame && g.depthM > 3.0 )
          out.push_back( { "P" + std::to_string( i ), image.id, g.pixelInImage + noisePx * Eigen::Vector2d( noise( rng ), noise( rng ) ), std::max( noisePx, 0.3 ) } );
      }
    }
    return out;
  }

  //! GNSS/INS-like start values: truth plus noise of the given sigmas, which are also the priors.
  std::vector<BundleImage> perturbed( const SurveyRun &run, std::mt19937 &rng, double sigmaM, double sigmaDeg )
  {
    std::normal_distribution<double> noise( 0.0, 1.0 );
    std::vector<BundleImage> out = run.truth;
    for ( BundleImage &image : out )
    {
      ExteriorOrientation &eo = image.exterior;
      eo.projectionCentre += sigmaM * Eigen::Vector3d( noise( rng ), noise( rng ), noise( rng ) );
      eo.omegaDeg += sigmaDeg * noise( rng );
      eo.phiDeg += sigmaDeg * noise( rng );
      eo.kappaDeg += sigmaDeg * noise( rng );
      eo.sigma = ExteriorSigma { sigmaM, sigmaM, sigmaM, sigmaDeg, sigmaDeg, sigmaDeg };
    }
    return out;
  }

  std::vector<ControlPoint> groundPoints( const SurveyRun &run, const std::vector<int> &control, const std::vector<int> &check )
  {
    std::vector<ControlPoint> out;
    for ( int i : control )
      out.push_back( { "P" + std::to_string( i ), run.points[i], Eigen::Vector3d::Zero(), false } );
    for ( int i : check )
      out.push_back( { "P" + std::to_string( i ), run.points[i], Eigen::Vector3d::Zero(), true } );
    return out;
  }

  const BundlePointResult &pointResult( const BundleSummary &s, const std::string &id )
  {
    return *std::find_if( s.points.begin(), s.points.end(), [&]( const BundlePointResult & p ) { return p.id == id; } );
  }
} // namespace

TEST( BundleAdjustment, NoiseFreeObservationsRecoverTheTruth )
{
  std::mt19937 rng( 1 );
  const SurveyRun run = highwayRun( 4, 80, rng );
  BundleOptions options;
  options.usePosePriors = false;
  const BundleSummary s = bundleAdjust( run.cameras, perturbed( run, rng, 0.2, 0.1 ), groundPoints( run, { 0, 1, 2, 3, 4, 5 }, {} ), observe( run, rng, 0.0 ), options );
  ASSERT_TRUE( s.ok() ) << s.message;
  EXPECT_LT( s.rmsPx, 1e-6 );
  for ( size_t i = 0; i < run.truth.size(); ++i )
  {
    EXPECT_LT( ( s.images[i].exterior.projectionCentre - run.truth[i].exterior.projectionCentre ).norm(), 1e-6 ) << run.truth[i].id;
    EXPECT_NEAR( s.images[i].exterior.kappaDeg, run.truth[i].exterior.kappaDeg, 1e-7 );
  }
  for ( const BundlePointResult &p : s.points )
    EXPECT_LT( ( p.world - run.points[std::stoi( p.id.substr( 1 ) )] ).norm(), 1e-6 ) << p.id;
}

TEST( BundleAdjustment, SelfCalibrationRecoversTheInterior )
{
  std::mt19937 rng( 2 );
  const SurveyRun run = highwayRun( 5, 150, rng );
  std::vector<Camera> start = run.cameras;
  for ( Camera &c : start )
  {
    c.f *= 1.01;
    c.cx += 3.0;
    c.cy -= 2.0;
  }
  std::vector<int> control;
  for ( int i = 0; i < 12; ++i )
    control.push_back( i );
  BundleOptions options;
  options.usePosePriors = false;
  options.freeInterior[kInteriorF] = options.freeInterior[kInteriorCx] = options.freeInterior[kInteriorCy] = true;
  const BundleSummary s = bundleAdjust( start, perturbed( run, rng, 0.1, 0.05 ), groundPoints( run, control, {} ), observe( run, rng, 0.0 ), options );
  ASSERT_TRUE( s.ok() ) << s.message;
  for ( size_t c = 0; c < run.cameras.size(); ++c )
  {
    EXPECT_NEAR( s.cameras[c].camera.f, run.cameras[c].f, 1e-4 ) << run.cameras[c].id;
    EXPECT_NEAR( s.cameras[c].camera.cx, run.cameras[c].cx, 1e-4 );
    EXPECT_NEAR( s.cameras[c].camera.cy, run.cameras[c].cy, 1e-4 );
    EXPECT_EQ( s.cameras[c].freeParameters, ( std::vector<std::string> { "f", "cx", "cy" } ) );
  }
}

TEST( BundleAdjustment, CheckPointsImproveOverTheRawGnssInsBlock )
{
  for ( unsigned seed : { 3u, 4u, 5u } )
  {
    std::mt19937 rng( seed );
    const SurveyRun run = highwayRun( 6, 200, rng );
    const std::vector<BundleImage> raw = perturbed( run, rng, 0.10, 0.03 );
    const std::vector<BundleObservation> observations = observe( run, rng, 0.3 );
    const std::vector<int> check { 10, 11, 12, 13, 14, 15, 16, 17 };
    const BundleSummary s = bundleAdjust( run.cameras, raw, groundPoints( run, { 0, 1, 2, 3 }, check ), observations );
    ASSERT_TRUE( s.ok() ) << s.message;
    EXPECT_EQ( s.checkCount, 8 );

    // The raw block: check points intersected with the GNSS/INS orientation.
    std::vector<std::unique_ptr<OrientedImage>> rawImages;
    for ( const BundleImage &image : raw )
      rawImages.push_back( std::make_unique<OrientedImage>( *std::find_if( run.cameras.begin(), run.cameras.end(), [&]( const Camera & c ) { return c.id == image.cameraId; } ), image.exterior ) );
    double rawSum = 0.0;
    for ( int i : check )
    {
      std::vector<RayObservation> rays;
      for ( const BundleObservation &o : observations )
        if ( o.pointId == "P" + std::to_string( i ) )
        {
          const size_t k = std::find_if( raw.begin(), raw.end(), [&]( const BundleImage & b ) { return b.id == o.imageId; } ) - raw.begin();
          rays.push_back( { rawImages[k].get(), o.pixelInImage, o.sigmaPx } );
        }
      const IntersectionSummary x = intersectRays( rays );
      ASSERT_TRUE( x.ok() );
      rawSum += ( x.point - run.points[i] ).squaredNorm();
    }
    const double rawRmse = std::sqrt( rawSum / check.size() );
    const double adjustedRmse = s.rmseCheckM.norm();
    EXPECT_LT( adjustedRmse, 0.8 * rawRmse ) << "seed " << seed << ": raw " << rawRmse << " m, adjusted " << adjustedRmse << " m";
    EXPECT_GT( s.sigma0, 0.7 );
    EXPECT_LT( s.sigma0, 1.3 );
  }
}

TEST( BundleAdjustment, ReportedSigmasMatchTheScatter )
{
  // 200 trials: GNSS/INS start and priors drawn from their sigmas, 0.3 px image noise.
  std::mt19937 setup( 6 );
  const SurveyRun run = highwayRun( 3, 60, setup );
  Eigen::Vector3d sumSquaresCentre = Eigen::Vector3d::Zero(), reportedCentre = Eigen::Vector3d::Zero();
  Eigen::Vector3d sumSquaresPoint = Eigen::Vector3d::Zero(), reportedPoint = Eigen::Vector3d::Zero();
  const int trials = 200;
  std::mt19937 rng( 7 );
  for ( int t = 0; t < trials; ++t )
  {
    const BundleSummary s = bundleAdjust( run.cameras, perturbed( run, rng, 0.10, 0.03 ), groundPoints( run, { 0, 1, 2 }, { 20 } ), observe( run, rng, 0.3 ) );
    ASSERT_TRUE( s.ok() ) << s.message;
    sumSquaresCentre += ( s.images[4].exterior.projectionCentre - run.truth[4].exterior.projectionCentre ).cwiseAbs2();
    reportedCentre += Eigen::Vector3d( s.images[4].exterior.sigma->x, s.images[4].exterior.sigma->y, s.images[4].exterior.sigma->z );
    const BundlePointResult &p = pointResult( s, "P20" );
    sumSquaresPoint += p.errorM.cwiseAbs2();
    reportedPoint += p.sigmaM;
  }
  const Eigen::Vector3d ratioCentre = ( sumSquaresCentre / trials ).cwiseSqrt().cwiseQuotient( reportedCentre / trials );
  const Eigen::Vector3d ratioPoint = ( sumSquaresPoint / trials ).cwiseSqrt().cwiseQuotient( reportedPoint / trials );
  for ( int k = 0; k < 3; ++k )
  {
    EXPECT_GT( ratioCentre[k], 0.8 ) << "centre axis " << k;
    EXPECT_LT( ratioCentre[k], 1.25 ) << "centre axis " << k;
    EXPECT_GT( ratioPoint[k], 0.8 ) << "point axis " << k;
    EXPECT_LT( ratioPoint[k], 1.25 ) << "point axis " << k;
  }
}

TEST( BundleAdjustment, EachObservationsResidualIsItsPointProjectedMinusTheMeasurement )
{
  std::mt19937 rng( 3 );
  const SurveyRun run = highwayRun( 3, 50, rng );
  const std::vector<BundleObservation> observations = observe( run, rng, 0.5 );
  const BundleSummary s = bundleAdjust( run.cameras, perturbed( run, rng, 0.10, 0.03 ), groundPoints( run, { 0, 1, 2 }, { 20 } ), observations );
  ASSERT_TRUE( s.ok() ) << s.message;
  ASSERT_EQ( s.observations.size(), observations.size() );
  double sumSquares = 0.0;
  for ( const BundleObservationResult &o : s.observations )
  {
    const BundleImageResult &image = *std::find_if( s.images.begin(), s.images.end(), [&]( const BundleImageResult &i ) { return i.id == o.imageId; } );
    const std::string cameraId = std::find_if( run.truth.begin(), run.truth.end(), [&]( const BundleImage &i ) { return i.id == o.imageId; } )->cameraId;
    const Camera &camera = std::find_if( s.cameras.begin(), s.cameras.end(), [&]( const BundleCameraResult &c ) { return c.camera.id == cameraId; } )->camera;
    const GroundProjection g = OrientedImage( camera, image.exterior ).projectGroundToPixel( pointResult( s, o.pointId ).world );
    ASSERT_TRUE( g.ok() );
    EXPECT_LT( ( o.residualPx - ( g.pixelInImage - o.pixelInImage ) ).norm(), 1e-6 ) << o.pointId << " in " << o.imageId;
    sumSquares += o.residualPx.squaredNorm();
  }
  EXPECT_NEAR( std::sqrt( sumSquares / ( 2.0 * s.observations.size() ) ), s.rmsPx, 1e-9 );
  EXPECT_GT( s.rmsPx, 0.2 );
}

TEST( BundleAdjustment, DatumAndInputProblemsAreReported )
{
  std::mt19937 rng( 8 );
  const SurveyRun run = highwayRun( 3, 40, rng );
  const std::vector<BundleObservation> observations = observe( run, rng, 0.0 );
  BundleOptions noPriors;
  noPriors.usePosePriors = false;
  const BundleSummary s = bundleAdjust( run.cameras, perturbed( run, rng, 0.1, 0.05 ), groundPoints( run, { 0, 1 }, {} ), observations, noPriors );
  EXPECT_EQ( s.status, BundleSummary::Status::NoDatum );
  EXPECT_NE( s.message.find( "datum" ), std::string::npos );

  std::vector<BundleObservation> withLonely = observations;
  withLonely.push_back( { "lonely", run.truth[0].id, Eigen::Vector2d( 100.0, 100.0 ), 0.5 } );
  const BundleSummary skipped = bundleAdjust( run.cameras, perturbed( run, rng, 0.1, 0.05 ), {}, withLonely );
  ASSERT_TRUE( skipped.ok() ) << skipped.message;
  EXPECT_NE( std::find( skipped.skippedPoints.begin(), skipped.skippedPoints.end(), "lonely" ), skipped.skippedPoints.end() );

  std::vector<BundleObservation> unknownImage = observations;
  unknownImage.push_back( { "P1", "nowhere", Eigen::Vector2d( 1.0, 1.0 ), 0.5 } );
  EXPECT_THROW( bundleAdjust( run.cameras, run.truth, {}, unknownImage ), std::invalid_argument );
  BundleOptions freeK1;
  freeK1.freeInterior[kInteriorK1] = true;
  EXPECT_THROW( bundleAdjust( run.cameras, run.truth, {}, observations, freeK1 ), std::invalid_argument );
}

TEST( BundleAdjustment, CancelStopsTheSolveBetweenIterations )
{
  std::mt19937 rng( 4 );
  const SurveyRun run = highwayRun( 4, 80, rng );
  const std::vector<BundleImage> start = perturbed( run, rng, 0.5, 0.3 );
  const std::vector<BundleObservation> observations = observe( run, rng, 0.3 );
  // without cancel: several iterations, converged
  std::vector<std::string> seen;
  BundleOptions watched;
  watched.progress = Progress( [&]( double fraction, const std::string &message ) {
    EXPECT_TRUE( fraction >= 0.0 && fraction <= 1.0 );
    seen.push_back( message );
  }, nullptr );
  const BundleSummary full = bundleAdjust( run.cameras, start, {}, observations, watched );
  ASSERT_TRUE( full.ok() ) << full.message;
  ASSERT_GE( seen.size(), 3u );
  EXPECT_EQ( seen.front().rfind( "iteration 0, cost ", 0 ), 0u ) << seen.front();
  // cancelled after the first iteration: stopped there, nothing adjusted returned
  int calls = 0;
  BundleOptions cancelled;
  cancelled.progress = Progress( nullptr, [&] { return ++calls >= 2; } );
  const BundleSummary stopped = bundleAdjust( run.cameras, start, {}, observations, cancelled );
  EXPECT_EQ( stopped.status, BundleSummary::Status::Cancelled );
  EXPECT_EQ( calls, 2 );
  EXPECT_TRUE( stopped.images.empty() );
  EXPECT_NE( stopped.message.find( "cancelled" ), std::string::npos );
}

TEST( BundleAdjustment, SparseSchurAgreesWithTheDenseOne )
{
  std::mt19937 rng( 5 );
  const SurveyRun run = highwayRun( 4, 80, rng );
  const std::vector<BundleImage> start = perturbed( run, rng, 0.5, 0.3 );
  const std::vector<BundleObservation> observations = observe( run, rng, 0.3 );
  const BundleSummary dense = bundleAdjust( run.cameras, start, {}, observations );
  ASSERT_TRUE( dense.ok() ) << dense.message;
  BundleOptions sparseOptions;
  sparseOptions.denseSchurMaxImages = 0; // every block is solved with the sparse Schur complement
  const BundleSummary sparse = bundleAdjust( run.cameras, start, {}, observations, sparseOptions );
  ASSERT_TRUE( sparse.ok() ) << sparse.message;
  EXPECT_NEAR( sparse.sigma0, dense.sigma0, 1e-6 );
  ASSERT_EQ( sparse.images.size(), dense.images.size() );
  for ( size_t i = 0; i < dense.images.size(); ++i )
  {
    EXPECT_LT( ( sparse.images[i].exterior.projectionCentre - dense.images[i].exterior.projectionCentre ).norm(), 1e-6 );
    EXPECT_NEAR( sparse.images[i].exterior.sigma->z, dense.images[i].exterior.sigma->z, 1e-6 );
  }
}

TEST( BundleAdjustment, BadOptionsAreRefusedByName )
{
  std::mt19937 rng( 6 );
  const SurveyRun run = highwayRun( 3, 40, rng );
  const std::vector<BundleImage> start = perturbed( run, rng, 0.5, 0.3 );
  const std::vector<BundleObservation> observations = observe( run, rng, 0.3 );
  const auto refused = [&]( const std::function<void( BundleOptions & )> &spoil, const std::string &named )
  {
    BundleOptions options;
    spoil( options );
    try
    {
      bundleAdjust( run.cameras, start, {}, observations, options );
      ADD_FAILURE() << "accepted: " << named;
    }
    catch ( const std::invalid_argument &e )
    {
      EXPECT_NE( std::string( e.what() ).find( named ), std::string::npos ) << e.what();
    }
  };
  refused( []( BundleOptions & o ) { o.maxIterations = 0; }, "iteration" );
  refused( []( BundleOptions & o ) { o.gradientTolerance = 2.0; }, "tolerances" );
  refused( []( BundleOptions & o ) { o.functionTolerance = -1e-9; }, "tolerances" );
  refused( []( BundleOptions & o ) { o.denseSchurMaxImages = -1; }, "dense Schur" );
  refused( []( BundleOptions & o ) { o.robust = true; o.robustThreshold = std::numeric_limits<double>::infinity(); }, "robust threshold" );
}

// Space resection against exact synthetic truth.
#include <functional>
#include <random>

#include <gtest/gtest.h>

#include "adjustment/intersection.h"
#include "adjustment/resection.h"
#include "vanrig.h"

using namespace geostation;

namespace
{
  //! Control spread in front of an image: on the road and up poles, in frame.
  std::vector<ControlPoint> controlFor( const OrientedImage &image, int count, std::mt19937 &rng, int checkCount = 0 )
  {
    std::uniform_real_distribution<double> along( 8.0, 40.0 ), across( -6.0, 6.0 ), height( 100.0, 106.0 );
    std::vector<ControlPoint> out;
    const Eigen::Vector3d base = image.exterior().projectionCentre;
    while ( static_cast<int>( out.size() ) < count + checkCount )
    {
      const Eigen::Vector3d p( base.x() + across( rng ), base.y() + along( rng ), height( rng ) );
      const GroundProjection g = image.projectGroundToPixel( p );
      if ( !g.ok() || !g.inFrame || g.pixelInImage.x() < 20 || g.pixelInImage.y() < 20 || g.pixelInImage.x() > image.camera().width - 20 || g.pixelInImage.y() > image.camera().height - 20 )
        continue;
      ControlPoint c;
      c.id = ( static_cast<int>( out.size() ) < count ? "GCP" : "CHK" ) + std::to_string( out.size() + 1 );
      c.world = p;
      c.check = static_cast<int>( out.size() ) >= count;
      out.push_back( c );
    }
    return out;
  }

  std::vector<ImagePoint> measure( const OrientedImage &image, const std::vector<ControlPoint> &control, std::mt19937 *rng = nullptr, double noisePx = 0.0 )
  {
    std::normal_distribution<double> noise( 0.0, 1.0 );
    std::vector<ImagePoint> out;
    for ( const ControlPoint &c : control )
    {
      Eigen::Vector2d pixel = image.projectGroundToPixel( c.world ).pixelInImage;
      if ( rng )
        pixel += noisePx * Eigen::Vector2d( noise( *rng ), noise( *rng ) );
      out.push_back( { c.id, pixel, 0.5 } );
    }
    return out;
  }

  Eigen::Matrix<double, 6, 1> poseVector( const ExteriorOrientation &eo )
  {
    Eigen::Matrix<double, 6, 1> v;
    v << eo.projectionCentre, eo.omegaDeg, eo.phiDeg, eo.kappaDeg;
    return v;
  }
} // namespace

class ResectionModels : public ::testing::TestWithParam<int>
{
};

TEST_P( ResectionModels, NoiseFreeControlRecoversTheOrientationFromNothing )
{
  const auto images = vanrig::images();
  const OrientedImage &truth = *images[GetParam()];
  std::mt19937 rng( 3 );
  const std::vector<ControlPoint> control = controlFor( truth, 10, rng );
  const ResectionSummary s = resectImage( truth.camera(), control, measure( truth, control ) );
  ASSERT_TRUE( s.ok() ) << s.message;
  EXPECT_TRUE( s.converged );
  EXPECT_LT( ( s.exterior.projectionCentre - truth.exterior().projectionCentre ).norm(), 1e-6 );
  EXPECT_NEAR( s.exterior.omegaDeg, truth.exterior().omegaDeg, 1e-7 );
  EXPECT_NEAR( s.exterior.phiDeg, truth.exterior().phiDeg, 1e-7 );
  EXPECT_NEAR( s.exterior.kappaDeg, truth.exterior().kappaDeg, 1e-7 );
  EXPECT_LT( s.rmseControlPx, 1e-6 );
  EXPECT_EQ( s.controlCount, 10 );
  EXPECT_EQ( s.redundancy, 14 );
  EXPECT_TRUE( s.blunders.empty() );
  ASSERT_EQ( s.parameterNames.size(), 6u );
  EXPECT_EQ( s.correlation.rows(), 6 );
  EXPECT_NEAR( s.correlation( 2, 2 ), 1.0, 1e-12 );
}

TEST_P( ResectionModels, FreeInteriorIsRecoveredToo )
{
  const auto images = vanrig::images();
  const OrientedImage &truth = *images[GetParam()];
  std::mt19937 rng( 4 );
  const std::vector<ControlPoint> control = controlFor( truth, 25, rng );
  Camera start = truth.camera();
  start.f *= 1.02;
  start.cx += 6.0;
  start.cy -= 4.0;
  ResectionOptions options;
  options.freeInterior[kInteriorF] = options.freeInterior[kInteriorCx] = options.freeInterior[kInteriorCy] = true;
  const ResectionSummary s = resectImage( start, control, measure( truth, control ), options );
  ASSERT_TRUE( s.ok() ) << s.message;
  EXPECT_NEAR( s.camera.f, truth.camera().f, 1e-5 );
  EXPECT_NEAR( s.camera.cx, truth.camera().cx, 1e-5 );
  EXPECT_NEAR( s.camera.cy, truth.camera().cy, 1e-5 );
  EXPECT_LT( ( s.exterior.projectionCentre - truth.exterior().projectionCentre ).norm(), 1e-6 );
  EXPECT_EQ( s.parameterNames.back(), "cy" );
  EXPECT_EQ( s.parameterNames.size(), 9u );
}

INSTANTIATE_TEST_SUITE_P( AllModels, ResectionModels, ::testing::Values( 0, 1, 2 ),
                          []( const auto & info ) { return std::string( info.param == 0 ? "opencv" : info.param == 1 ? "none" : "brown_photo" ); } );

TEST( Resection, ReportedSigmasMatchTheScatter )
{
  // 200 Monte Carlo trials, 12 control points, 0.5 px noise.
  const auto images = vanrig::images();
  const OrientedImage &truth = *images[0];
  std::mt19937 rng( 21 );
  const std::vector<ControlPoint> control = controlFor( truth, 12, rng );
  const Eigen::Matrix<double, 6, 1> truePose = poseVector( truth.exterior() );
  Eigen::Matrix<double, 6, 1> sumSquares = Eigen::Matrix<double, 6, 1>::Zero(), reported = Eigen::Matrix<double, 6, 1>::Zero();
  const int trials = 200;
  for ( int t = 0; t < trials; ++t )
  {
    ResectionOptions options;
    options.removeBlunders = false;
    const ResectionSummary s = resectImage( truth.camera(), control, measure( truth, control, &rng, 0.5 ), options );
    ASSERT_TRUE( s.ok() ) << s.message;
    sumSquares += ( poseVector( s.exterior ) - truePose ).cwiseAbs2();
    for ( int k = 0; k < 6; ++k )
      reported[k] += s.sigmas[k];
  }
  const Eigen::Matrix<double, 6, 1> empirical = ( sumSquares / trials ).cwiseSqrt();
  reported /= trials;
  for ( int k = 0; k < 6; ++k )
  {
    const double ratio = empirical[k] / reported[k];
    EXPECT_GT( ratio, 0.8 ) << "parameter " << k << ": empirical " << empirical[k] << " reported " << reported[k];
    EXPECT_LT( ratio, 1.25 ) << "parameter " << k << ": empirical " << empirical[k] << " reported " << reported[k];
  }
}

TEST( Resection, CheckPointErrorIsCloseToTheBestPossible )
{
  // With 10 control points, the check points' ground error must stay within
  // 1.5 x of what the true orientation gives for the same noisy measurements.
  const auto images = vanrig::images();
  const OrientedImage &truth = *images[1];
  std::mt19937 rng( 33 );
  const std::vector<ControlPoint> points = controlFor( truth, 10, rng, 6 );
  double sumEstimated = 0.0, sumBest = 0.0;
  int count = 0;
  for ( int t = 0; t < 200; ++t )
  {
    const std::vector<ImagePoint> measured = measure( truth, points, &rng, 0.5 );
    const ResectionSummary s = resectImage( truth.camera(), points, measured );
    ASSERT_TRUE( s.ok() ) << s.message;
    ASSERT_EQ( s.checkCount, 6 );
    sumEstimated += s.rmseCheckM * s.rmseCheckM * s.checkCount;
    for ( size_t i = 0; i < points.size(); ++i )
      if ( points[i].check )
      {
        const PlaneIntersectionSummary best = intersectRayWithPlane( { &truth, measured[i].pixelInImage, 0.5 }, Plane::horizontal( points[i].world.z() ) );
        sumBest += ( best.point - points[i].world ).head<2>().squaredNorm();
        ++count;
      }
  }
  const double ratio = std::sqrt( sumEstimated / count ) / std::sqrt( sumBest / count );
  EXPECT_LT( ratio, 1.5 ) << "estimated " << std::sqrt( sumEstimated / count ) << " m, best " << std::sqrt( sumBest / count ) << " m";
  EXPECT_GE( ratio, 1.0 - 1e-9 );
}

TEST( Resection, ABlunderIsNamedAndRemoved )
{
  const auto images = vanrig::images();
  const OrientedImage &truth = *images[2];
  std::mt19937 rng( 8 );
  const std::vector<ControlPoint> control = controlFor( truth, 10, rng );
  std::vector<ImagePoint> measured = measure( truth, control, &rng, 0.3 );
  measured[6].pixelInImage += Eigen::Vector2d( 9.0, -7.0 ); // GCP7 misidentified
  const ResectionSummary s = resectImage( truth.camera(), control, measured );
  ASSERT_TRUE( s.ok() ) << s.message;
  ASSERT_EQ( s.blunders, std::vector<std::string> { "GCP7" } );
  EXPECT_NE( s.message.find( "GCP7" ), std::string::npos );
  EXPECT_EQ( s.controlCount, 9 );
  EXPECT_LT( ( s.exterior.projectionCentre - truth.exterior().projectionCentre ).norm(), 0.1 );
  const auto gcp7 = std::find_if( s.residuals.begin(), s.residuals.end(), []( const PointResidual & r ) { return r.pointId == "GCP7"; } );
  ASSERT_NE( gcp7, s.residuals.end() );
  EXPECT_TRUE( gcp7->blunder );
  EXPECT_GT( gcp7->residualPx.norm(), 8.0 );

  // Without removal the point is flagged but kept.
  ResectionOptions keep;
  keep.removeBlunders = false;
  const ResectionSummary k = resectImage( truth.camera(), control, measured, keep );
  ASSERT_TRUE( k.ok() );
  EXPECT_TRUE( k.blunders.empty() );
  EXPECT_EQ( k.controlCount, 10 );
  int flagged = 0;
  for ( const PointResidual &r : k.residuals )
    flagged += r.blunder ? 1 : 0;
  EXPECT_GE( flagged, 1 );
}

TEST( Resection, RobustLossResistsABlunderItKeeps )
{
  const auto images = vanrig::images();
  const OrientedImage &truth = *images[0];
  std::mt19937 rng( 14 );
  const std::vector<ControlPoint> control = controlFor( truth, 12, rng );
  std::vector<ImagePoint> measured = measure( truth, control, &rng, 0.3 );
  measured[3].pixelInImage += Eigen::Vector2d( 25.0, 18.0 );
  ResectionOptions plain, robust;
  plain.removeBlunders = robust.removeBlunders = false;
  robust.robust = true;
  const ResectionSummary p = resectImage( truth.camera(), control, measured, plain );
  const ResectionSummary r = resectImage( truth.camera(), control, measured, robust );
  ASSERT_TRUE( p.ok() && r.ok() );
  const double plainError = ( p.exterior.projectionCentre - truth.exterior().projectionCentre ).norm();
  const double robustError = ( r.exterior.projectionCentre - truth.exterior().projectionCentre ).norm();
  EXPECT_LT( robustError, 0.3 * plainError ) << "plain " << plainError << " m, robust " << robustError << " m";
}

TEST( Resection, ControlSigmasWidenThePrecision )
{
  const auto images = vanrig::images();
  const OrientedImage &truth = *images[1];
  std::mt19937 rng( 9 );
  std::vector<ControlPoint> control = controlFor( truth, 8, rng );
  const ResectionSummary fixed = resectImage( truth.camera(), control, measure( truth, control ), [] { ResectionOptions o; o.scaleCovarianceBySigma0 = false; return o; }() );
  for ( ControlPoint &c : control )
    c.sigmaM = Eigen::Vector3d( 0.05, 0.05, 0.05 );
  const ResectionSummary loose = resectImage( truth.camera(), control, measure( truth, control ), [] { ResectionOptions o; o.scaleCovarianceBySigma0 = false; return o; }() );
  ASSERT_TRUE( fixed.ok() && loose.ok() );
  EXPECT_LT( ( loose.exterior.projectionCentre - truth.exterior().projectionCentre ).norm(), 1e-6 );
  for ( int k = 0; k < 6; ++k )
    EXPECT_GT( loose.sigmas[k], fixed.sigmas[k] ) << k;
}

TEST( Resection, BadGeometryAndInputAreReported )
{
  const auto images = vanrig::images();
  const OrientedImage &truth = *images[1];
  std::mt19937 rng( 10 );
  std::vector<ControlPoint> control = controlFor( truth, 6, rng );

  // Too few points.
  std::vector<ControlPoint> three( control.begin(), control.begin() + 3 );
  ResectionSummary s = resectImage( truth.camera(), three, measure( truth, three ) );
  EXPECT_EQ( s.status, ResectionSummary::Status::TooFewPoints );
  EXPECT_NE( s.message.find( "at least 4" ), std::string::npos ) << s.message;

  // Collinear control: points along one line.
  std::vector<ControlPoint> line;
  for ( int i = 0; i < 6; ++i )
    line.push_back( { "L" + std::to_string( i ), truth.exterior().projectionCentre + Eigen::Vector3d( 1.0, 10.0 + 4.0 * i, -2.0 ), Eigen::Vector3d::Zero(), false } );
  s = resectImage( truth.camera(), line, measure( truth, line ) );
  EXPECT_EQ( s.status, ResectionSummary::Status::DegenerateControl );
  EXPECT_NE( s.message.find( "line" ), std::string::npos ) << s.message;

  // Flat control under a nadir camera with f free: f and the height trade off.
  Camera nadirCamera = vanrig::camera( DistortionModel::None );
  ExteriorOrientation nadir;
  nadir.projectionCentre = { 500000.0, 4400000.0, 1100.0 };
  const OrientedImage aerial( nadirCamera, nadir );
  std::vector<ControlPoint> flat;
  for ( int i = 0; i < 9; ++i )
    flat.push_back( { "F" + std::to_string( i ), { 500000.0 + 150.0 * ( i % 3 - 1 ), 4400000.0 + 120.0 * ( i / 3 - 1 ), 100.0 }, Eigen::Vector3d::Zero(), false } );
  ResectionOptions freeF;
  freeF.freeInterior[kInteriorF] = true;
  s = resectImage( nadirCamera, flat, measure( aerial, flat ), freeF );
  EXPECT_EQ( s.status, ResectionSummary::Status::DegenerateControl ) << s.message;
  EXPECT_NE( s.message.find( "cannot determine" ), std::string::npos ) << s.message;

  // Inconsistent input throws.
  std::vector<ImagePoint> twice = measure( truth, control );
  twice.push_back( twice.front() );
  EXPECT_THROW( resectImage( truth.camera(), control, twice ), std::invalid_argument );
  std::vector<ImagePoint> zeroSigma = measure( truth, control );
  zeroSigma[0].sigmaPx = 0.0;
  EXPECT_THROW( resectImage( truth.camera(), control, zeroSigma ), std::invalid_argument );
  ResectionOptions freeK1;
  freeK1.freeInterior[kInteriorK1] = true;
  EXPECT_THROW( resectImage( truth.camera(), control, measure( truth, control ), freeK1 ), std::invalid_argument );
  // Bad options throw, naming the value.
  const auto refused = [&]( const std::function<void( ResectionOptions & )> &spoil, const std::string &named )
  {
    ResectionOptions options;
    spoil( options );
    try
    {
      resectImage( truth.camera(), control, measure( truth, control ), options );
      ADD_FAILURE() << "accepted: " << named;
    }
    catch ( const std::invalid_argument &e )
    {
      EXPECT_NE( std::string( e.what() ).find( named ), std::string::npos ) << e.what();
    }
  };
  refused( []( ResectionOptions & o ) { o.maxIterations = 0; }, "iteration" );
  refused( []( ResectionOptions & o ) { o.functionTolerance = 0.0; }, "tolerances" );
  refused( []( ResectionOptions & o ) { o.parameterTolerance = std::nan( "" ); }, "tolerances" );
  refused( []( ResectionOptions & o ) { o.blunderThreshold = -1.0; }, "blunder threshold" );
  refused( []( ResectionOptions & o ) { o.robust = true; o.robustThreshold = 0.0; }, "robust threshold" );
}

TEST( Resection, SolverTolerancesComeFromTheOptions )
{
  const auto images = vanrig::images();
  const OrientedImage &truth = *images[1];
  std::mt19937 rng( 13 );
  const std::vector<ControlPoint> control = controlFor( truth, 8, rng );
  std::vector<ImagePoint> measured = measure( truth, control );
  std::normal_distribution<double> noise( 0.0, 0.5 );
  for ( ImagePoint &p : measured )
    p.pixelInImage += Eigen::Vector2d( noise( rng ), noise( rng ) );
  const ResectionSummary tight = resectImage( truth.camera(), control, measured );
  ASSERT_TRUE( tight.ok() ) << tight.message;
  // loose tolerances stop the same solve earlier, a little further from the optimum
  ResectionOptions loose;
  loose.functionTolerance = loose.gradientTolerance = loose.parameterTolerance = 0.5;
  const ResectionSummary early = resectImage( truth.camera(), control, measured, loose );
  ASSERT_TRUE( early.ok() ) << early.message;
  EXPECT_LT( early.iterations, tight.iterations );
  EXPECT_GE( early.sigma0, tight.sigma0 - 1e-12 );
}

TEST( Resection, UnmatchedObservationsAreCounted )
{
  const auto images = vanrig::images();
  const OrientedImage &truth = *images[1];
  std::mt19937 rng( 12 );
  const std::vector<ControlPoint> control = controlFor( truth, 6, rng );
  std::vector<ImagePoint> measured = measure( truth, control );
  measured.push_back( { "tie_17", { 100.0, 100.0 }, 0.5 } );
  const ResectionSummary s = resectImage( truth.camera(), control, measured );
  ASSERT_TRUE( s.ok() );
  EXPECT_EQ( s.unmatchedObservations, 1 );
}

TEST( Resection, APointAloneInACornerIsHardlyChecked )
{
  // eight points in one part of the photo and one alone far from them: the alone one pulls the orientation to
  // itself, so little of an error in it shows in its residual (its redundancy number is small)
  const auto images = vanrig::images();
  const OrientedImage &truth = *images[2];
  const Eigen::Vector3d base = truth.exterior().projectionCentre;
  std::vector<ControlPoint> control;
  std::mt19937 rng( 3 );
  std::uniform_real_distribution<double> along( 25.0, 40.0 ), across( -3.0, 3.0 ), height( 100.0, 106.0 );
  while ( control.size() < 8 )
  {
    const Eigen::Vector3d p( base.x() + across( rng ), base.y() + along( rng ), height( rng ) );
    const GroundProjection g = truth.projectGroundToPixel( p );
    if ( g.ok() && g.inFrame )
      control.push_back( { "GCP" + std::to_string( control.size() + 1 ), p, Eigen::Vector3d::Zero(), false } );
  }
  // the alone one: near, low and to the side
  const Eigen::Vector3d alone( base.x() + 4.5, base.y() + 9.0, 100.0 );
  ASSERT_TRUE( truth.projectGroundToPixel( alone ).inFrame );
  control.push_back( { "ALONE", alone, Eigen::Vector3d::Zero(), false } );
  const ResectionSummary s = resectImage( truth.camera(), control, measure( truth, control, &rng, 0.3 ) );
  ASSERT_TRUE( s.ok() ) << s.message;
  double aloneRedundancy = -1.0, leastOfTheOthers = 1.0;
  for ( const PointResidual &r : s.residuals )
  {
    EXPECT_GE( r.redundancy, 0.0 );
    EXPECT_LE( r.redundancy, 1.0 );
    if ( r.pointId == "ALONE" )
      aloneRedundancy = r.redundancy;
    else
      leastOfTheOthers = std::min( leastOfTheOthers, r.redundancy );
  }
  std::printf( "redundancy: alone %.3f, the others at least %.3f\n", aloneRedundancy, leastOfTheOthers );
  EXPECT_GE( aloneRedundancy, 0.0 );
  EXPECT_LT( aloneRedundancy, 0.4 );
  EXPECT_GT( leastOfTheOthers, aloneRedundancy + 0.2 );
}

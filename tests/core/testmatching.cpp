// Area-based matching: the correlation measures, the parabola peak, least-
// squares matching and the epipolar band search, on simulated aerial stereo
// imagery (noise and blur on) against the simulator's exact truth.
#include <cmath>
#include <random>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <Eigen/QR>
#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>
#include <opencv2/imgcodecs.hpp>

#include "geometry/epipolar.h"
#include "matching/areamatcher.h"
#include "matching/multiimagematcher.h"
#include "simulation/degradation.h"
#include "simulation/renderer.h"
#include "simulation/surveyrig.h"
#include "simulation/surveysimulator.h"

using namespace geostation;

namespace
{
  //! A rendered aerial stereo pair and its scene, for truth.
  struct StereoPair
  {
    BuiltScene built;
    Block truth, noisy;
    cv::Mat left, right; //!< 8-bit RGB
    std::unique_ptr<OrientedImage> leftImage, rightImage;
    std::unique_ptr<MatchImage> leftMatch, rightMatch;
  };

  const StereoPair &aerialPair()
  {
    static std::unique_ptr<StereoPair> pair;
    if ( pair )
      return *pair;
    pair = std::make_unique<StereoPair>();
    SimulationOptions options;
    options.preset = SurveyPreset::AerialStereo;
    options.seed = 17;
    options.imageWidth = 768;
    options.imageHeight = 768;
    options.stations = 2;
    options.outputDir = "unused";
    const RigSettings settings = rigSettings( options );
    const SceneRequest request = sceneRequest( options, settings );
    pair->built = buildScene( request );
    buildRig( options, settings, pair->built, pair->truth, pair->noisy );
    DegradationOptions degradation;
    degradation.noiseSigma = 1.0;
    degradation.blurSigmaPx = 0.5;
    RenderOptions render;
    render.threads = 2;
    for ( int k = 0; k < 2; ++k )
    {
      const BlockImage &image = pair->truth.images[k];
      auto oriented = std::make_unique<OrientedImage>( pair->truth.orientedImage( image ) );
      const cv::Mat rgb = degradeAndQuantise( renderImage( *pair->built.scene, *oriented, nullptr, render ), degradation, 100 + k );
      ( k == 0 ? pair->left : pair->right ) = rgb;
      ( k == 0 ? pair->leftImage : pair->rightImage ) = std::move( oriented );
    }
    pair->leftMatch = std::make_unique<MatchImage>( pair->left );
    pair->rightMatch = std::make_unique<MatchImage>( pair->right );
    return *pair;
  }

  struct TruthPoint
  {
    Eigen::Vector2d left, right;
  };

  /**
   * Points of the left image on open ground (every sample of a 15 x 15
   * window sees the terrain, not an object), seen in the right image, with
   * their exact conjugate pixels.
   */
  std::vector<TruthPoint> groundPoints( const StereoPair &pair, int count, uint32_t seed )
  {
    std::mt19937 random( seed );
    std::uniform_real_distribution<double> u( 40.0, 728.0 );
    std::vector<TruthPoint> points;
    const Scene &scene = *pair.built.scene;
    while ( static_cast<int>( points.size() ) < count )
    {
      const Eigen::Vector2d p( u( random ), u( random ) );
      // one surface (same material, no shadow or paint edge, no object) under the whole window
      bool open = true;
      uint32_t key = 0;
      for ( int dy = -8; dy <= 8 && open; ++dy )
        for ( int dx = -8; dx <= 8 && open; ++dx )
        {
          const Ray ray = *pair.leftImage->worldRayFromPixel( p + Eigen::Vector2d( dx, dy ) );
          const SurfaceSample sample = scene.trace( ray.origin, ray.direction, 1e-3 );
          open = sample.ground && ( ( dx == -8 && dy == -8 ) || sample.key == key );
          key = sample.key;
        }
      if ( !open )
        continue;
      const Ray ray = *pair.leftImage->worldRayFromPixel( p );
      const SurfaceSample hit = scene.trace( ray.origin, ray.direction, 1e-3 );
      const Eigen::Vector3d ground = ray.origin + hit.t * ray.direction;
      const GroundProjection q = pair.rightImage->projectGroundToPixel( ground );
      if ( !q.ok() || q.pixelInImage.x() < 40 || q.pixelInImage.y() < 40 || q.pixelInImage.x() > 728 || q.pixelInImage.y() > 728 )
        continue;
      if ( !scene.isVisible( pair.rightImage->exterior().projectionCentre, ground, -1, 0.02 ) )
        continue;
      // the conjugate window, too, sees only open ground
      for ( int dy = -8; dy <= 8 && open; dy += 4 )
        for ( int dx = -8; dx <= 8 && open; dx += 4 )
        {
          const Ray other = *pair.rightImage->worldRayFromPixel( q.pixelInImage + Eigen::Vector2d( dx, dy ) );
          open = scene.trace( other.origin, other.direction, 1e-3 ).ground;
        }
      if ( !open )
        continue;
      // Gruen's model holds: the true mapping of the 15 x 15 window is affine to 0.01 px
      // (not so on the curved embankments beside the roads)
      std::vector<Eigen::Vector2d> from, to;
      for ( int dy = -7; dy <= 7; dy += 7 )
        for ( int dx = -7; dx <= 7; dx += 7 )
        {
          const Ray r = *pair.leftImage->worldRayFromPixel( p + Eigen::Vector2d( dx, dy ) );
          const SurfaceSample s = scene.trace( r.origin, r.direction, 1e-3 );
          from.emplace_back( dx, dy );
          to.push_back( pair.rightImage->projectGroundToPixel( r.origin + s.t * r.direction ).pixelInImage );
        }
      Eigen::MatrixXd A( 9, 3 );
      Eigen::MatrixXd B( 9, 2 );
      for ( int k = 0; k < 9; ++k )
      {
        A.row( k ) << from[k].x(), from[k].y(), 1.0;
        B.row( k ) = to[k].transpose();
      }
      const Eigen::MatrixXd X = A.colPivHouseholderQr().solve( B );
      if ( ( A * X - B ).rowwise().norm().maxCoeff() > 0.01 )
        continue;
      points.push_back( { p, q.pixelInImage } );
    }
    return points;
  }

  cv::Mat texture( int width, int height, uint32_t seed )
  {
    cv::Mat noise( height, width, CV_32F );
    cv::RNG rng( seed );
    rng.fill( noise, cv::RNG::NORMAL, 0.0, 40.0 );
    cv::GaussianBlur( noise, noise, cv::Size( 0, 0 ), 1.5 );
    cv::Mat out;
    noise.convertTo( out, CV_8U, 1.0, 128.0 );
    return out;
  }

  /**
   * Texture in every direction (Förstner): the gradient structure tensor of
   * the w x w window, as RMS gradients along its weaker and stronger axes.
   */
  std::pair<double, double> textureStrength( const MatchImage &image, const Eigen::Vector2d &pixel, int w )
  {
    Eigen::Matrix2d n = Eigen::Matrix2d::Zero();
    const int c0 = static_cast<int>( pixel.x() ), r0 = static_cast<int>( pixel.y() );
    for ( int r = r0 - w / 2; r <= r0 + w / 2; ++r )
      for ( int c = c0 - w / 2; c <= c0 + w / 2; ++c )
      {
        const cv::Mat &v = image.value();
        const Eigen::Vector2d g( 0.5 * ( v.at<float>( r, c + 1 ) - v.at<float>( r, c - 1 ) ), 0.5 * ( v.at<float>( r + 1, c ) - v.at<float>( r - 1, c ) ) );
        n += g * g.transpose();
      }
    const Eigen::Vector2d eigen = Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>( n / ( w * w ) ).eigenvalues();
    return { std::sqrt( std::max( 0.0, eigen.x() ) ), std::sqrt( std::max( 0.0, eigen.y() ) ) };
  }
}

TEST( Similarity, MeasuresOnIdenticalShiftedAndScaledWindows )
{
  const cv::Mat a = texture( 80, 60, 1 );
  cv::Mat brighter;
  a.convertTo( brighter, CV_8U, 0.7, 40.0 ); // other exposure: ncc stays 1, cc does not
  const MatchImage reference( a ), other( brighter );
  for ( SimilarityMeasure m : { SimilarityMeasure::CC, SimilarityMeasure::NCC, SimilarityMeasure::WCC, SimilarityMeasure::WNCC } )
  {
    const CorrelationTemplate t( reference, 40, 30, 15, 15, m );
    ASSERT_TRUE( t.valid() ) << t.reason();
    EXPECT_NEAR( *t.score( reference, 40, 30 ), 1.0, 1e-9 ) << similarityMeasureName( m );
    // a shifted window scores lower: much lower for the normalised measures
    EXPECT_LT( *t.score( reference, 43, 30 ), ( m == SimilarityMeasure::NCC || m == SimilarityMeasure::WNCC ) ? 0.9 : 0.9999 ) << similarityMeasureName( m );
  }
  EXPECT_GT( *CorrelationTemplate( reference, 40, 30, 15, 15, SimilarityMeasure::NCC ).score( other, 40, 30 ), 0.995 );
  EXPECT_GT( *CorrelationTemplate( reference, 40, 30, 3, 15, SimilarityMeasure::WNCC ).score( other, 40, 30 ), 0.99 );
  // cc is not normalised for the mean: it sees the exposure change, ncc does not
  EXPECT_LT( *CorrelationTemplate( reference, 40, 30, 15, 15, SimilarityMeasure::CC ).score( other, 40, 30 ), 0.99995 );
  // Xin's (1995) 5 x 5 weights: 5 at the centre, 2 at the border
  EXPECT_DOUBLE_EQ( centreWeight( 0, 0, 5, 5 ), 5.0 );
  EXPECT_DOUBLE_EQ( centreWeight( 2, -1, 5, 5 ), 2.0 );
  EXPECT_NEAR( centreWeight( 1, 1, 5, 5 ), 2.75, 1e-12 );
}

TEST( Similarity, DenseScoresEqualScoresAtEveryPosition )
{
  cv::Mat a = texture( 120, 90, 3 );
  a( cv::Rect( 70, 50, 30, 25 ) ).setTo( 128 ); // a flat patch: no scores there
  const MatchImage image( a );
  for ( SimilarityMeasure m : { SimilarityMeasure::CC, SimilarityMeasure::NCC, SimilarityMeasure::WNCC } )
    for ( const cv::Size window : { cv::Size( 15, 15 ), cv::Size( 3, 15 ), cv::Size( 21, 9 ) } )
    {
      const CorrelationTemplate t( image, 40, 35, window.width, window.height, m );
      ASSERT_TRUE( t.valid() );
      // centres reaching over every border of the image
      const cv::Rect centres( -5, -4, 132, 100 );
      const cv::Mat dense = t.scoreArea( image, centres );
      ASSERT_EQ( dense.rows, centres.height );
      ASSERT_EQ( dense.cols, centres.width );
      int scored = 0, none = 0;
      for ( int r = 0; r < dense.rows; ++r )
        for ( int c = 0; c < dense.cols; ++c )
        {
          const std::optional<double> one = t.score( image, centres.x + c, centres.y + r );
          const double d = dense.at<double>( r, c );
          if ( one )
          {
            ASSERT_NEAR( d, *one, 1e-12 ) << similarityMeasureName( m ) << " " << c << "," << r;
            ++scored;
          }
          else
          {
            ASSERT_TRUE( std::isnan( d ) ) << c << "," << r;
            ++none;
          }
        }
      EXPECT_GT( scored, 5000 );
      EXPECT_GT( none, 1000 );
    }
}

TEST( Similarity, BadWindowsGiveReasonsNotScores )
{
  const MatchImage image( texture( 60, 40, 2 ) );
  EXPECT_EQ( CorrelationTemplate( image, 3, 20, 15, 15, SimilarityMeasure::NCC ).reason(), "the window leaves the reference image" );
  EXPECT_FALSE( CorrelationTemplate( image, 30, 20, 14, 15, SimilarityMeasure::NCC ).valid() );
  const MatchImage flat( cv::Mat( 40, 40, CV_8U, cv::Scalar( 90 ) ) );
  EXPECT_EQ( CorrelationTemplate( flat, 20, 20, 15, 15, SimilarityMeasure::NCC ).reason(), "the window is flat (no texture to correlate)" );
  EXPECT_TRUE( CorrelationTemplate( flat, 20, 20, 15, 15, SimilarityMeasure::NCC ).flat() );
  EXPECT_FALSE( CorrelationTemplate( image, 3, 20, 15, 15, SimilarityMeasure::NCC ).flat() );
  const CorrelationTemplate t( image, 30, 20, 15, 15, SimilarityMeasure::NCC );
  EXPECT_FALSE( t.score( image, 55, 20 ).has_value() ); // leaves the search image
  EXPECT_FALSE( t.score( flat, 20, 20 ).has_value() );  // flat search window
  EXPECT_THROW( MatchImage( cv::Mat( 10, 10, CV_32F ) ), std::invalid_argument );
  // LSM on a flat window, and a window leaving the image
  const LsmResult onFlat = leastSquaresMatch( flat, { 20, 20 }, flat, { 20, 20 } );
  EXPECT_FALSE( onFlat.converged() );
  EXPECT_EQ( onFlat.status, LsmResult::Status::Flat );
  EXPECT_TRUE( onFlat.degenerate() );
  const LsmResult leaving = leastSquaresMatch( image, { 2, 20 }, image, { 20, 20 } );
  EXPECT_EQ( leaving.status, LsmResult::Status::Outside );
  EXPECT_EQ( leaving.message, "the window leaves the reference image" );
  EXPECT_EQ( lsmStatusName( leaving.status ), "outside" );
  // the search window running off the search image
  EXPECT_EQ( leastSquaresMatch( image, { 30, 20 }, image, { 56, 20 } ).status, LsmResult::Status::Outside );
  // bad options are the caller's error: one sentence, thrown
  LsmOptions even;
  even.windowWidth = 8;
  EXPECT_THROW( leastSquaresMatch( image, { 30, 20 }, image, { 30, 20 }, even ), std::invalid_argument );
  LsmOptions noIterations;
  noIterations.maxIterations = 0;
  EXPECT_THROW( noIterations.check(), std::invalid_argument );
  AreaMatchOptions area;
  area.lsmOptions.windowWidth = 1;
  area.lsmOptions.windowHeight = 1;
  EXPECT_THROW( area.check(), std::invalid_argument );
  area.lsm = false;
  EXPECT_NO_THROW( area.check() );
}

TEST( Similarity, ParabolaFindsTheVertex )
{
  const auto f = []( double x ) { return 0.9 - 0.3 * ( x - 0.23 ) * ( x - 0.23 ); };
  EXPECT_NEAR( parabolaPeakOffset( f( -1 ), f( 0 ), f( 1 ) ), 0.23, 1e-12 );
  EXPECT_EQ( parabolaPeakOffset( 0.5, 0.4, 0.6 ), 0.0 ); // not a peak
}

TEST( LeastSquaresMatching, SubPixelAndConvergenceOnSimulatedAerialStereo )
{
  // Thesis §5.1.2 against truth: from starts within 2 px of the true
  // conjugate point, LSM (25 x 25) converges (>= 99 %) to <= 0.025 px RMS on
  // open textured ground, noise (1 grey level) and blur (0.5 px) on, and is
  // at least 3 x better than the parabola fit of the NCC peak. Measured:
  // 100 %, 0.024 px RMS, parabola 0.115 px.
  const StereoPair &pair = aerialPair();
  const std::vector<TruthPoint> points = groundPoints( pair, 1500, 5 );
  std::mt19937 random( 9 );
  std::uniform_real_distribution<double> angle( 0, 2 * M_PI ), radius( 0, 2.0 );
  int converged = 0, textured = 0, bilinearConverged = 0;
  double lsmSq = 0.0, parabolaSq = 0.0, bilinearSq = 0.0;
  int parabolaCount = 0;
  AreaMatchOptions correlation;
  correlation.lsm = false;
  correlation.minScore = 0.0;
  for ( const TruthPoint &p : points )
  {
    const CorrelationTemplate t( *pair.leftMatch, static_cast<int>( p.left.x() ), static_cast<int>( p.left.y() ), 15, 15, SimilarityMeasure::NCC );
    const auto [weak, strong] = textureStrength( *pair.leftMatch, p.left, 15 );
    if ( !t.valid() || weak < 3.0 || weak < 0.4 * strong )
      continue; // not a textured surface: flat, or a linear feature (the aperture problem)
    ++textured;
    const double a = angle( random ), r = radius( random );
    const Eigen::Vector2d start = p.right + r * Eigen::Vector2d( std::cos( a ), std::sin( a ) );
    LsmOptions lsmOptions;
    lsmOptions.windowWidth = lsmOptions.windowHeight = 25;
    lsmOptions.maxShiftPx = 4.0;
    const LsmResult lsm = leastSquaresMatch( *pair.leftMatch, p.left, *pair.rightMatch, start, lsmOptions );
    if ( lsm.converged() )
    {
      ++converged;
      lsmSq += ( lsm.pixelInImage - p.right ).squaredNorm();
    }
    // Xin's (1995) bilinear resampling, for comparison
    lsmOptions.resampling = LsmOptions::Resampling::Bilinear;
    const LsmResult bilinear = leastSquaresMatch( *pair.leftMatch, p.left, *pair.rightMatch, start, lsmOptions );
    if ( bilinear.converged() )
    {
      ++bilinearConverged;
      bilinearSq += ( bilinear.pixelInImage - p.right ).squaredNorm();
    }
    const AreaMatch ncc = matchAroundPosition( *pair.leftMatch, p.left, *pair.rightMatch, p.right, 3.0, correlation );
    if ( ncc.score > 0.5 )
    {
      parabolaSq += ( ncc.correlationPixel - p.right ).squaredNorm();
      ++parabolaCount;
    }
  }
  ASSERT_GT( textured, 200 );
  const double convergence = static_cast<double>( converged ) / textured;
  const double lsmRms = std::sqrt( lsmSq / converged ), parabolaRms = std::sqrt( parabolaSq / parabolaCount );
  std::cout << "LSM: " << converged << "/" << textured << " converged, RMS " << lsmRms << " px; NCC + parabola RMS " << parabolaRms << " px (" << parabolaCount << ")"
            << "; bilinear LSM " << bilinearConverged << " converged, RMS " << std::sqrt( bilinearSq / std::max( 1, bilinearConverged ) ) << " px\n";
  EXPECT_GE( static_cast<double>( bilinearConverged ) / textured, 0.99 );
  EXPECT_LE( std::sqrt( bilinearSq / std::max( 1, bilinearConverged ) ), 0.025 );
  EXPECT_GE( convergence, 0.99 );
  EXPECT_LE( lsmRms, 0.025 );
  EXPECT_GE( parabolaRms / lsmRms, 3.0 );
}

TEST( AreaMatcher, EpipolarBandSearchFindsTheConjugatePoint )
{
  const StereoPair &pair = aerialPair();
  const std::vector<TruthPoint> points = groundPoints( pair, 150, 6 );
  // the noisy block's orientation: the band absorbs its error
  const OrientedImage left = pair.noisy.orientedImage( pair.noisy.images[0] ), right = pair.noisy.orientedImage( pair.noisy.images[1] );
  EpipolarOptions epipolar;
  const double flyingHeight = left.exterior().projectionCentre.z() - pair.built.scene->terrain().minHeight();
  epipolar.minDistanceM = 0.6 * flyingHeight;
  epipolar.maxDistanceM = 1.2 * flyingHeight;
  epipolar.maxSegmentPx = 4.0;
  AreaMatchOptions options;
  int tried = 0, matched = 0, correct = 0;
  double sq = 0.0;
  for ( const TruthPoint &p : points )
  {
    const CorrelationTemplate t( *pair.leftMatch, static_cast<int>( p.left.x() ), static_cast<int>( p.left.y() ), 15, 15, SimilarityMeasure::NCC );
    if ( !t.valid() || t.contrast() < 3.0 )
      continue;
    ++tried;
    std::vector<Eigen::Vector2d> curve;
    for ( const auto &piece : epipolarCurve( left, p.left, right, epipolar ).pieces )
      for ( const EpipolarVertex &v : piece )
        curve.push_back( v.pixelInImage );
    const AreaMatch m = matchAlongEpipolarBand( *pair.leftMatch, p.left, *pair.rightMatch, curve, options );
    if ( !m.matched() )
      continue;
    ++matched;
    const double error = ( m.pixelInImage - p.right ).norm();
    if ( error < 1.0 )
    {
      ++correct;
      sq += error * error;
    }
  }
  std::cout << "epipolar band: " << matched << "/" << tried << " matched, " << correct << " within 1 px, RMS " << std::sqrt( sq / std::max( 1, correct ) ) << " px\n";
  EXPECT_GE( static_cast<double>( correct ) / tried, 0.9 );
  EXPECT_GE( static_cast<double>( correct ) / matched, 0.97 );
}

TEST( LeastSquaresMatching, RecoversAKnownAffineShift )
{
  // An analytic texture (sinusoids below 0.3 cycles per pixel), sampled
  // exactly: the search image is the reference under a known affine
  // transformation and another exposure, so the truth carries no
  // interpolation error.
  std::mt19937 random( 4 );
  std::uniform_real_distribution<double> frequency( -0.3, 0.3 ), phase( 0, 2 * M_PI ), amplitude( 5, 15 );
  std::vector<std::array<double, 4>> waves;
  for ( int k = 0; k < 24; ++k )
    waves.push_back( { frequency( random ), frequency( random ), phase( random ), amplitude( random ) } );
  const auto f = [&]( double x, double y )
  {
    double v = 128.0;
    for ( const auto &w : waves )
      v += w[3] * std::sin( 2 * M_PI * ( w[0] * x + w[1] * y ) + w[2] );
    return v;
  };
  const Eigen::Vector2d centre( 60.3, 50.8 ), shift( 2.3, -1.4 );
  Eigen::Matrix2d A;
  const double s = 1.03, th = 0.04;
  A << s * std::cos( th ), -s * std::sin( th ), s * std::sin( th ), s * std::cos( th );
  const Eigen::Matrix2d inverse = A.inverse();
  cv::Mat reference( 100, 120, CV_16U ), search( 100, 120, CV_16U ); // 16-bit: the scaling keeps the precision
  for ( int r = 0; r < 100; ++r )
    for ( int c = 0; c < 120; ++c )
    {
      const Eigen::Vector2d p( c + 0.5, r + 0.5 );
      reference.at<uint16_t>( r, c ) = static_cast<uint16_t>( std::lround( 200.0 * f( p.x(), p.y() ) ) );
      // search(x_s) = 0.8 reference(x_r) + 30 with x_s = A (x_r - centre) + centre + shift
      const Eigen::Vector2d q = inverse * ( p - centre - shift ) + centre;
      search.at<uint16_t>( r, c ) = static_cast<uint16_t>( std::lround( 200.0 * ( 0.8 * f( q.x(), q.y() ) + 30.0 ) ) );
    }
  const MatchImage ref( reference ), sea( search );
  LsmOptions options;
  options.windowWidth = options.windowHeight = 11;
  const LsmResult r = leastSquaresMatch( ref, centre, sea, centre + shift + Eigen::Vector2d( 1.2, -0.9 ), options );
  ASSERT_TRUE( r.converged() ) << r.message;
  // bicubic resampling of sinusoids up to 0.3 cycles per pixel: 0.013 px
  EXPECT_LT( ( r.pixelInImage - ( centre + shift ) ).norm(), 0.02 ) << r.pixelInImage.transpose() << " iterations " << r.iterations;
  EXPECT_LT( ( r.affine - A ).norm(), 0.01 );

  // Xin's (1995) bilinear resampling converges too, less precisely on this texture
  options.resampling = LsmOptions::Resampling::Bilinear;
  const LsmResult b = leastSquaresMatch( ref, centre, sea, centre + shift + Eigen::Vector2d( 1.2, -0.9 ), options );
  ASSERT_TRUE( b.converged() ) << b.message << " after " << b.iterations << " iterations at " << b.pixelInImage.transpose() << " (truth " << ( centre + shift ).transpose() << ")";
  const double bilinearError = ( b.pixelInImage - ( centre + shift ) ).norm();
  std::cout << "LSM on exact sinusoids: B-spline " << ( r.pixelInImage - ( centre + shift ) ).norm() << " px, bilinear " << bilinearError << " px\n";
  EXPECT_LT( bilinearError, 0.15 );
  EXPECT_GT( bilinearError, ( r.pixelInImage - ( centre + shift ) ).norm() );
}

namespace
{
  //! Three nadir views of flat ground with a repetitive texture: stripes every 1.2 m along the strip, weak detail.
  //! The third camera's base differs from the first's, as between stations of a run or cameras of a rig.
  struct RepetitiveStrip
  {
    std::unique_ptr<Scene> scene;
    std::vector<std::unique_ptr<OrientedImage>> images;
    std::vector<std::unique_ptr<MatchImage>> pixels;
  };

  const RepetitiveStrip &repetitiveStrip()
  {
    static std::unique_ptr<RepetitiveStrip> strip;
    if ( strip )
      return *strip;
    strip = std::make_unique<RepetitiveStrip>();
    const double x0 = 500000.0, y0 = 4400000.0;
    HeightField ground( x0 - 100, y0 + 100, 1.0, 201, 201, []( double, double ) { return 100.0; } );
    auto ortho = std::make_shared<OrthoTexture>();
    ortho->originX = x0 - 100;
    ortho->originY = y0 + 100;
    ortho->pixelSizeM = 0.05;
    ortho->rgb = cv::Mat( 4000, 4000, CV_8UC3 );
    cv::Mat detail( 4000, 4000, CV_32F );
    cv::RNG rng( 5 );
    rng.fill( detail, cv::RNG::NORMAL, 0.0, 12.0 );
    cv::GaussianBlur( detail, detail, cv::Size( 0, 0 ), 3.0 );
    for ( int r = 0; r < 4000; ++r )
      for ( int c = 0; c < 4000; ++c )
      {
        const double x = c * 0.05;
        const uint8_t v = cv::saturate_cast<uint8_t>( 120 + 60 * std::sin( 2 * M_PI * x / 1.2 ) + detail.at<float>( r, c ) );
        ortho->rgb.at<cv::Vec3b>( r, c ) = cv::Vec3b( v, v, v );
      }
    strip->scene = std::make_unique<Scene>( std::move( ground ), RoadNetwork(), std::vector<SceneObject>(), std::vector<GroundMark>(), SceneLighting(), 1 );
    strip->scene->setOrtho( ortho );
    Camera camera;
    camera.id = "nadir";
    camera.width = 400;
    camera.height = 400;
    camera.f = 500;
    camera.cx = camera.cy = 200;
    DegradationOptions noise;
    noise.noiseSigma = 3.0;
    RenderOptions render;
    render.threads = 2;
    for ( int k = 0; k < 3; ++k )
    {
      ExteriorOrientation eo;
      // bases of 8 m and 11.5 m: the stripes' period does not repeat in both
      eo.projectionCentre = Eigen::Vector3d( x0 + ( k == 0 ? -8.0 : k == 1 ? 0.0 : 11.5 ), y0, 150.0 );
      strip->images.push_back( std::make_unique<OrientedImage>( camera, eo ) );
      const cv::Mat rgb = degradeAndQuantise( renderImage( *strip->scene, *strip->images.back(), nullptr, render ), noise, 50 + k );
      strip->pixels.push_back( std::make_unique<MatchImage>( rgb ) );
    }
    return *strip;
  }
}

TEST( MultiImageMatching, CutsWrongMatchesOnRepetitiveTexture )
{
  // Xin's (1995) multi-image matching (§5.4): candidates of the master pair are
  // kept only when the third image confirms them. Wrong-match rates (matched
  // more than 1 px from the truth) are measured for each correlation measure
  // alone and for the multi-image procedure.
  const RepetitiveStrip &strip = repetitiveStrip();
  EpipolarOptions epipolar;
  epipolar.minDistanceM = 25.0;
  epipolar.maxDistanceM = 100.0;
  epipolar.maxSegmentPx = 4.0;
  std::mt19937 random( 8 );
  std::uniform_real_distribution<double> u( 130.0, 270.0 ); // inside all three images
  std::map<std::string, std::pair<int, int>> pairCounts; // measure -> (matched, wrong)
  int multiMatched = 0, multiWrong = 0, tried = 0;
  for ( int k = 0; k < 120; ++k )
  {
    const Eigen::Vector2d p( u( random ), u( random ) );
    const Ray ray = *strip.images[1]->worldRayFromPixel( p );
    const Eigen::Vector3d ground = ray.origin + ( ( 100.0 - ray.origin.z() ) / ray.direction.z() ) * ray.direction;
    const Eigen::Vector2d truthLeft = strip.images[0]->projectGroundToPixel( ground ).pixelInImage;
    ++tried;
    std::vector<Eigen::Vector2d> curve;
    for ( const auto &piece : epipolarCurve( *strip.images[1], p, *strip.images[0], epipolar ).pieces )
      for ( const EpipolarVertex &v : piece )
        curve.push_back( v.pixelInImage );
    for ( SimilarityMeasure m : { SimilarityMeasure::CC, SimilarityMeasure::NCC, SimilarityMeasure::WCC, SimilarityMeasure::WNCC } )
    {
      AreaMatchOptions options;
      options.measure = m;
      const AreaMatch single = matchAlongEpipolarBand( *strip.pixels[1], p, *strip.pixels[0], curve, options );
      if ( single.matched() )
      {
        ++pairCounts[similarityMeasureName( m )].first;
        pairCounts[similarityMeasureName( m )].second += ( single.pixelInImage - truthLeft ).norm() > 1.0 ? 1 : 0;
      }
    }
    MultiImageMatchOptions options;
    options.epipolar = epipolar;
    const MultiImageMatch multi = matchMultiImage( { { strip.images[0].get(), strip.pixels[0].get() }, { strip.images[1].get(), strip.pixels[1].get() },
      { strip.images[2].get(), strip.pixels[2].get() } }, 1, 0, p, options );
    if ( multi.matched() )
    {
      ++multiMatched;
      multiWrong += ( *multi.pixels[0] - truthLeft ).norm() > 1.0 || ( multi.world - ground ).norm() > 0.2 ? 1 : 0;
    }
  }
  const double nccRate = static_cast<double>( pairCounts["ncc"].second ) / std::max( 1, pairCounts["ncc"].first );
  const double multiRate = static_cast<double>( multiWrong ) / std::max( 1, multiMatched );
  for ( const auto &[name, counts] : pairCounts )
    std::cout << "pair " << name << ": " << counts.first << "/" << tried << " matched, wrong " << 100.0 * counts.second / std::max( 1, counts.first ) << " %\n";
  std::cout << "multi-image ncc: " << multiMatched << "/" << tried << " matched, wrong " << 100.0 * multiRate << " %\n";
  EXPECT_GT( nccRate, 0.1 ) << "the texture is not repetitive enough to test anything";
  EXPECT_LT( multiRate, 0.5 * nccRate );
  EXPECT_GE( multiMatched, tried / 2 );
}

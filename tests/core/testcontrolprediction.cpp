// The semi-automatic mode (issue 18, item 2): with the orientation roughly
// known (the photo's GNSS/INS values) and four points measured by the
// operator, every other control point is predicted, found in a window
// around its prediction and checked by the resection. Against the
// simulator's truth: found points within 0.5 px, anything wrong flagged.
// GEOSTATION_PREDICTION_DEBUG=dir prints every point and writes crops.
#include <gtest/gtest.h>

#include <filesystem>
#include <iostream>
#include <random>
#include <unistd.h>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "identification/controlprediction.h"
#include "identification/markcandidates.h"
#include "io/block.h"
#include "io/rasterfile.h"
#include "simulation/surveysimulator.h"
#include "simulationtruth.h"

using namespace geostation;

namespace
{
  struct Scored
  {
    int predictedVisible = 0, within = 0, large = 0, largeWithin = 0, wrongUnflagged = 0, wrongFlagged = 0, flaggedRight = 0;
    int measurable = 0, measurableWithin = 0; // disc of 8 px or more, 90 % of it in view and in sunlight
    double worstFoundPx = 0.0;
  };

  Scored runSeed( uint32_t seed, bool scanned )
  {
    SimulationOptions options;
    options.preset = SurveyPreset::ObliquePhoto;
    options.seed = seed;
    options.scannedFilm = scanned;
    options.degradation.noiseSigma = 2.0;
    options.outputDir = std::filesystem::temp_directory_path() / ( "geostation-prediction-" + std::to_string( seed ) + "-" + std::to_string( ::getpid() ) );
    std::filesystem::remove_all( options.outputDir );
    simulateSurvey( options );
    // the scanned film is taken with its true inner orientation: the camera's nominal pixels are then the scan's
    const Block block = Block::load( options.outputDir / ( scanned ? "truth.geostation.json" : "block.geostation.json" ) );
    const Block noisy = Block::load( options.outputDir / "block.geostation.json" );
    const BlockImage &image = block.images.front();
    const TruthTable truth = readTruth( options.outputDir / "truth.gpkg" );
    cv::Mat grey = markGrey( readRaster( block.imageFilePath( image ).string() ).pixels );
    Camera camera = block.cameraOf( image );
    if ( scanned )
    {
      EXPECT_TRUE( image.innerOrientation.has_value() );
      // undo the scan affine so the test works in nominal pixels, as the dock does after inner orientation
      grey = nominalImage( grey, camera, nominalFromScanAffine( camera, *image.innerOrientation ) );
    }
    // the truth in the camera's nominal pixels (no scan affine)
    const Block truthBlock = Block::load( options.outputDir / "truth.geostation.json" );
    const OrientedImage exact( truthBlock.cameraOf( truthBlock.images.front() ), *truthBlock.images.front().exterior );
    std::vector<ControlPoint> control;
    for ( const auto &[id, world] : truth.control )
      control.push_back( { id, world, Eigen::Vector3d::Zero(), false } );
    // four points measured by the operator, spread over the photo
    std::vector<std::pair<double, std::string>> visible;
    for ( const auto &[key, pixel] : truth.imageTruth )
      if ( key.second == image.id && truth.control.count( key.first ) )
        visible.emplace_back( pixel.x(), key.first );
    std::sort( visible.begin(), visible.end() );
    EXPECT_GE( visible.size(), 8u );
    std::mt19937 random( seed );
    std::normal_distribution<double> gauss( 0.0, 0.3 );
    std::vector<ImagePoint> measured;
    for ( size_t k : { size_t( 0 ), visible.size() / 3, 2 * visible.size() / 3, visible.size() - 1 } )
    {
      const Eigen::Vector2d truePx = exact.projectGroundToPixel( truth.control.at( visible[k].second ) ).pixelInImage;
      measured.push_back( { visible[k].second, truePx + Eigen::Vector2d( gauss( random ), gauss( random ) ), 0.5 } );
    }

    const ControlPredictionSummary result = predictAndFindControl( grey, camera, *noisy.images.front().exterior, control, measured );
    EXPECT_TRUE( result.ok() ) << result.message;
    Scored s;
    for ( const PredictedPoint &p : result.points )
    {
      const bool shown = std::any_of( visible.begin(), visible.end(), [&]( const auto &v ) { return v.second == p.pointId; } );
      const Eigen::Vector2d truePx = exact.projectGroundToPixel( truth.control.at( p.pointId ) ).pixelInImage;
      s.predictedVisible += shown ? 1 : 0;
      // the white disc in the image, as the truth measures it on the rendered terrain: under 8 px it is a speck;
      // a target partly hidden (by a tree, a house, a fiducial mark) or partly in shadow cannot be centred
      // to 0.5 px by anyone
      const auto disc = truth.targetDiscs.find( { p.pointId, image.id } );
      const bool isLarge = shown && disc != truth.targetDiscs.end() && disc->second.px >= 8.0;
      const bool isMeasurable = isLarge && disc->second.inView >= 0.9 && disc->second.inSun >= 0.9;
      s.large += isLarge ? 1 : 0;
      s.measurable += isMeasurable ? 1 : 0;
      if ( std::getenv( "GEOSTATION_PREDICTION_DEBUG" ) )
      {
        const cv::Rect box = cv::Rect( static_cast<int>( truePx.x() ) - 12, static_cast<int>( truePx.y() ) - 12, 25, 25 ) & cv::Rect( 0, 0, grey.cols, grey.rows );
        cv::Mat crop;
        if ( box.area() > 0 )
          cv::resize( grey( box ), crop, cv::Size(), 10, 10, cv::INTER_NEAREST );
        if ( !crop.empty() )
          cv::imwrite( std::string( std::getenv( "GEOSTATION_PREDICTION_DEBUG" ) ) + "/" + std::to_string( seed ) + "_" + p.pointId + ".png", crop );
      }
      if ( std::getenv( "GEOSTATION_PREDICTION_DEBUG" ) && disc != truth.targetDiscs.end() )
        std::cout << "  " << p.pointId << " disc " << disc->second.px << " px, in view " << disc->second.inView << ", in sun " << disc->second.inSun << "\n";
      if ( std::getenv( "GEOSTATION_PREDICTION_DEBUG" ) )
        std::cout << "  " << p.pointId << ( shown ? " shown " : " hidden " ) << predictedPointStatusName( p.status ) << " " << p.reason << " true " << truePx.transpose()
                  << " predicted " << p.predictedPx.transpose() << " found " << p.pixelInImage.transpose() << "\n";
      if ( p.status != PredictedPoint::Status::Found && p.status != PredictedPoint::Status::Flagged )
        continue;
      const double error = ( p.pixelInImage - truePx ).norm();
      const bool right = shown && error < 1.5;
      if ( p.status == PredictedPoint::Status::Found )
      {
        s.within += shown && error <= 0.5 ? 1 : 0;
        s.largeWithin += isLarge && error <= 0.5 ? 1 : 0;
        s.measurableWithin += isMeasurable && error <= 0.5 ? 1 : 0;
        s.wrongUnflagged += right ? 0 : 1;
        s.worstFoundPx = std::max( s.worstFoundPx, right ? error : 0.0 );
        if ( !right )
          std::cout << "  " << p.pointId << " accepted " << error << " px from its true pixel" << ( shown ? "" : " (hidden)" ) << "\n";
      }
      else
      {
        s.wrongFlagged += right ? 0 : 1;
        s.flaggedRight += right ? 1 : 0;
      }
    }
    std::cout << ( scanned ? "scanned film" : "digital" ) << " seed " << seed << ": " << result.message << "; " << s.within << " of " << s.predictedVisible
              << " predicted points in view found within 0.5 px (" << s.largeWithin << " of the " << s.large << " of 8 px or more, " << s.measurableWithin << " of the "
              << s.measurable << " of those in full view and sunlight; worst found " << s.worstFoundPx << " px), " << s.wrongFlagged << " wrong flagged, " << s.flaggedRight
              << " right flagged, " << s.wrongUnflagged << " wrong accepted; sigma0 " << result.resection.sigma0 << "\n";
    std::filesystem::remove_all( options.outputDir );
    return s;
  }
} // namespace

TEST( ControlPrediction, MarkCentreOfARenderedTarget )
{
  // a white disc on a black square on grass-grey, anti-aliased by area, 7.3 px across, at a known sub-pixel centre
  cv::Mat grey( 64, 64, CV_8U, cv::Scalar( 90 ) );
  const Eigen::Vector2d centre( 31.37, 30.81 );
  for ( int r = 0; r < 64; ++r )
    for ( int c = 0; c < 64; ++c )
    {
      double sum = 0.0;
      for ( int sr = 0; sr < 8; ++sr )
        for ( int sc = 0; sc < 8; ++sc )
        {
          const Eigen::Vector2d p( c + ( sc + 0.5 ) / 8, r + ( sr + 0.5 ) / 8 );
          const Eigen::Vector2d d = p - centre;
          sum += d.norm() <= 3.65 ? 235.0 : ( std::max( std::abs( d.x() ), std::abs( d.y() ) ) <= 5.8 ? 20.0 : 90.0 );
        }
      grey.at<uint8_t>( r, c ) = static_cast<uint8_t>( std::lround( sum / 64 ) );
    }
  const std::optional<Eigen::Vector2d> found = markCentre( grey, centre + Eigen::Vector2d( 1.2, -0.9 ), 7.3 );
  ASSERT_TRUE( found );
  EXPECT_LT( ( *found - centre ).norm(), 0.05 ) << found->transpose();
  EXPECT_FALSE( markCentre( cv::Mat( 64, 64, CV_8U, cv::Scalar( 90 ) ), centre, 7.3 ) ); // no mark
  EXPECT_FALSE( markCentre( grey, Eigen::Vector2d( 2, 2 ), 7.3 ) );                       // the window leaves the image
}

TEST( ControlPrediction, MarkCentreOfALongEllipseWithinItsOutline )
{
  // a target seen at a grazing angle: a white disc drawn as an ellipse 12 x 2.4 px (turned 20 degrees) on its
  // black square, with bright ground 1 px beyond the square's edge across the ellipse, anti-aliased by area
  const Eigen::Vector2d centre( 40.31, 30.77 );
  const double angle = 20.0 * M_PI / 180.0;
  Eigen::Matrix2d discShape; // unit circle -> pixel offsets of the disc's outline
  discShape << 6.0 * std::cos( angle ), -1.2 * std::sin( angle ), 6.0 * std::sin( angle ), 1.2 * std::cos( angle );
  const Eigen::Matrix2d unitFromPixel = discShape.inverse();
  cv::Mat grey( 64, 80, CV_8U );
  for ( int r = 0; r < grey.rows; ++r )
    for ( int c = 0; c < grey.cols; ++c )
    {
      double sum = 0.0;
      for ( int sr = 0; sr < 8; ++sr )
        for ( int sc = 0; sc < 8; ++sc )
        {
          const Eigen::Vector2d u = unitFromPixel * ( Eigen::Vector2d( c + ( sc + 0.5 ) / 8, r + ( sr + 0.5 ) / 8 ) - centre );
          sum += u.norm() <= 1.0 ? 235.0 : ( u.cwiseAbs().maxCoeff() <= 1.6 ? 20.0 : 200.0 );
        }
      grey.at<uint8_t>( r, c ) = static_cast<uint8_t>( std::lround( sum / 64 ) );
    }
  const Eigen::Vector2d start = centre + Eigen::Vector2d( 0.6, -0.4 );
  const std::optional<Eigen::Vector2d> inOutline = markCentreInEllipse( grey, start, discShape );
  ASSERT_TRUE( inOutline );
  // (across the ellipse the square reaches only 0.72 px beyond the disc: the ground's light bleeds into the
  // square's rim pixels there, which costs a quarter of a pixel; measured 0.26 px)
  EXPECT_LT( ( *inOutline - centre ).norm(), 0.3 ) << inOutline->transpose();
  // the round window of the ellipse's length takes in the bright ground beside it and finds no mark
  EXPECT_FALSE( markCentre( grey, start, 12.0 ) );
  EXPECT_FALSE( markCentreInEllipse( cv::Mat( 64, 80, CV_8U, cv::Scalar( 90 ) ), centre, discShape ) ); // no mark
  EXPECT_FALSE( markCentreInEllipse( grey, Eigen::Vector2d( 3, 3 ), discShape ) );                      // the window leaves the image
}

TEST( ControlPrediction, PredictedControlFoundAndFlaggedOnSimulatedPhotos )
{
  // six simulated oblique photos (four digital, two scanned film), GNSS/INS orientation (2 m, 0.5 degrees)
  Scored total;
  for ( const auto &[seed, scanned] : { std::pair<uint32_t, bool>( 8, false ), std::pair<uint32_t, bool>( 21, false ), std::pair<uint32_t, bool>( 5, true ),
                                         std::pair<uint32_t, bool>( 13, false ), std::pair<uint32_t, bool>( 34, false ), std::pair<uint32_t, bool>( 9, true ) } )
  {
    const Scored s = runSeed( seed, scanned );
    total.predictedVisible += s.predictedVisible;
    total.large += s.large;
    total.largeWithin += s.largeWithin;
    total.measurable += s.measurable;
    total.measurableWithin += s.measurableWithin;
    total.within += s.within;
    total.wrongUnflagged += s.wrongUnflagged;
    total.wrongFlagged += s.wrongFlagged;
    total.flaggedRight += s.flaggedRight;
    total.worstFoundPx = std::max( total.worstFoundPx, s.worstFoundPx );
  }
  const double rate = static_cast<double>( total.within ) / std::max( 1, total.predictedVisible );
  std::cout << "semi-automatic: " << total.within << " of " << total.predictedVisible << " (" << rate << ") within 0.5 px; " << total.wrongFlagged << " wrong, all flagged; "
            << total.wrongUnflagged << " wrong accepted; " << total.flaggedRight << " right points flagged; of the " << total.large
            << " whose disc covers 8 px or more, " << total.largeWithin << " within 0.5 px; of the " << total.measurable
            << " of those with 90 % of the disc in view and in sunlight, " << total.measurableWithin << " within 0.5 px\n";
  const double measurableRate = static_cast<double>( total.measurableWithin ) / std::max( 1, total.measurable );
  // measured: 39 of the 42 targets a surveyor would measure (a white disc of 8 px or more, 90 % of it in view
  // and in sunlight) are found within 0.5 px (0.93, the aim is 0.9); of the three missed, scanned film seed 5's
  // GCP001 (a long ellipse, 5 % hidden) and GCP016 (alone at the photo's edge: redundancy 0.15, which the resection
  // cannot check) are flagged, seed 34's GCP052 (9 px, a long ellipse) found 1 px off. Of every target whose
  // centre the truth sees, 48 of 72 (0.67): the others are specks of 0.8-7 px (a grazing view, a slope facing
  // away), half hidden by a house, a tree or a fiducial mark's square, or partly in a tree's shadow. No wrong
  // point is accepted unflagged: GCP034 of seed 8 (its centre hidden, texture found 2.3 px off, alone low in the
  // photo, redundancy 0.32) was, until a found mark the other points hardly check was flagged and the final
  // orientation taken without the flagged ones.
  EXPECT_GE( measurableRate, 0.9 );
  EXPECT_GE( total.measurable, 35 );
  EXPECT_GE( rate, 0.65 );
  EXPECT_EQ( total.wrongUnflagged, 0 );
}

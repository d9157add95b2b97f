// How much of a line its band carries (bandSupport(), verification.h): the
// extraction's final lines with a dead end go where it is low. A road shows
// its band along nearly all its length, past a car and across a shadow; a
// chain through a field's grain and its scattered trees finds one only here
// and there; a straight line across a plain field finds none. And whether
// the band keeps its width: a strip of field converging on a road widens
// steadily along its line.
#include <gtest/gtest.h>

#include <random>
#include <stdexcept>

#include <opencv2/imgproc.hpp>

#include "extraction/coincidentextraction.h"
#include "extraction/verification.h"

using namespace geostation;

namespace
{
  /**
   * 400 x 300: a grass field (grain of 20 grey levels over blobs of about 6 px, and 60 dark trees of 5 px with
   * their shadows), a dark road 10 px wide along row 150 with a bright car on it and a shadow across half of it.
   */
  cv::Mat fieldWithARoad()
  {
    std::mt19937 random( 11 );
    cv::Mat coarse( 50, 67, CV_32F );
    cv::randn( coarse, 0.0, 20.0 );
    cv::Mat grain;
    cv::resize( coarse, grain, cv::Size( 400, 300 ), 0, 0, cv::INTER_CUBIC );
    cv::Mat grey( 300, 400, CV_8U );
    for ( int r = 0; r < 300; ++r )
      for ( int c = 0; c < 400; ++c )
        grey.at<uint8_t>( r, c ) = cv::saturate_cast<uint8_t>( 120.0 + grain.at<float>( r, c ) );
    std::uniform_int_distribution<int> col( 0, 399 ), row( 0, 299 );
    for ( int k = 0; k < 60; ++k )
    {
      const cv::Point at( col( random ), row( random ) );
      if ( std::abs( at.y - 150 ) < 14 )
        continue;
      cv::ellipse( grey, at + cv::Point( 3, 2 ), cv::Size( 5, 3 ), 30.0, 0.0, 360.0, cv::Scalar( 70 ), cv::FILLED );
      cv::circle( grey, at, 3, cv::Scalar( 85 ), cv::FILLED );
    }
    grey( cv::Rect( 0, 145, 400, 10 ) ).setTo( 60 );
    grey( cv::Rect( 180, 147, 12, 5 ) ).setTo( 200 ); // a car
    grey( cv::Rect( 260, 140, 18, 10 ) ).setTo( 40 ); // a shadow across the road's northern half
    cv::Mat noise( grey.size(), CV_8S );
    cv::randn( noise, 0.0, 3.0 );
    cv::Mat out;
    grey.convertTo( out, CV_16S );
    cv::Mat n16;
    noise.convertTo( n16, CV_16S );
    out += n16;
    out.convertTo( grey, CV_8U );
    return grey;
  }

  LineObjectOptions roads()
  {
    LineObjectOptions object;
    object.polarity = 0;
    object.minContrast = 18.0;
    object.minWidthPx = 6.0;
    object.maxWidthPx = 30.0;
    return object;
  }
} // namespace

TEST( BandSupport, ARoadCarriesItsLineAndAFieldDoesNot )
{
  const GreyTiles grey( fieldWithARoad() );
  const double road = bandSupport( grey, { Eigen::Vector2d( 10.0, 150.0 ), Eigen::Vector2d( 390.0, 150.0 ) }, roads() ).share;
  // a chain through the grain, wandering across the field as REM's chains do
  std::vector<Eigen::Vector2d> chain;
  for ( int i = 0; i <= 40; ++i )
    chain.emplace_back( 20.0 + 9.0 * i, 60.0 + 6.0 * std::sin( 0.7 * i ) + 0.3 * i );
  const double field = bandSupport( grey, chain, roads() ).share;
  std::printf( "band support: the road %.2f, a chain through the field %.2f\n", road, field );
  EXPECT_GE( road, 0.9 );
  EXPECT_LT( field, 0.5 );
  // the default keeps the road and not the chain
  const double minimum = CoincidentExtractionOptions().minBandSupport;
  EXPECT_GE( road, minimum );
  EXPECT_LT( field, minimum );
}

TEST( BandSupport, AShortLineCountsAsCarriedAndBadOptionsThrow )
{
  const GreyTiles grey( fieldWithARoad() );
  EXPECT_DOUBLE_EQ( bandSupport( grey, { Eigen::Vector2d( 50.0, 60.0 ), Eigen::Vector2d( 52.0, 60.0 ) }, roads() ).share, 1.0 );
  EXPECT_DOUBLE_EQ( bandSupport( grey, {}, roads() ).share, 1.0 );
  // repeated vertices do not make a direction of nothing
  const double repeated = bandSupport( grey, { Eigen::Vector2d( 10.0, 150.0 ), Eigen::Vector2d( 10.0, 150.0 ), Eigen::Vector2d( 100.0, 150.0 ) }, roads() ).share;
  EXPECT_GE( repeated, 0.9 );
  CoincidentExtractionOptions options;
  options.minBandSupport = 1.5;
  EXPECT_THROW( options.check(), std::invalid_argument );
  options.minBandSupport = -0.1;
  EXPECT_THROW( options.check(), std::invalid_argument );
  options = CoincidentExtractionOptions();
  options.maxBandWidening = 0.9;
  EXPECT_THROW( options.check(), std::invalid_argument );
}

TEST( BandSupport, AJunctionsMouthDoesNotCount )
{
  // a road along row 150 ending at a road 30 px wide across it (columns 290-319): the last profiles of the first
  // road lie inside the second, a band of no width; trimmed at that end they do not count
  cv::Mat grey( 300, 400, CV_8U, cv::Scalar( 130 ) );
  grey( cv::Rect( 0, 145, 305, 10 ) ).setTo( 60 );
  grey( cv::Rect( 290, 0, 30, 300 ) ).setTo( 60 );
  const GreyTiles tiles( grey );
  const std::vector<Eigen::Vector2d> line = { Eigen::Vector2d( 200.0, 150.0 ), Eigen::Vector2d( 305.0, 150.0 ) };
  const double untrimmed = bandSupport( tiles, line, roads() ).share, trimmed = bandSupport( tiles, line, roads(), false, true ).share;
  std::printf( "band support up to a junction: %.2f, beyond its mouth %.2f\n", untrimmed, trimmed );
  EXPECT_LT( untrimmed, 0.95 );
  EXPECT_GE( trimmed, 0.99 );
}

TEST( BandSupport, AStripWideningAlongTheLineIsNoRoad )
{
  // a bright strip of field between a darker field and a road (rows 150-159), from 8 px wide at column 20 to
  // 28 px at column 380, its upper border straight and slanting; and a road 20 px wide all along for comparison
  cv::Mat grey( 300, 400, CV_8U, cv::Scalar( 100 ) );
  grey( cv::Rect( 0, 150, 400, 10 ) ).setTo( 60 );
  for ( int c = 0; c < 400; ++c )
  {
    const int top = static_cast<int>( std::lround( 142.0 - 20.0 * ( c - 20 ) / 360.0 ) );
    grey( cv::Rect( c, top, 1, 150 - top ) ).setTo( 190 );
  }
  grey( cv::Rect( 0, 230, 400, 20 ) ).setTo( 190 );
  const GreyTiles tiles( grey );
  std::vector<Eigen::Vector2d> strip;
  for ( int c = 20; c <= 380; c += 20 )
    strip.emplace_back( c, 0.5 * ( 142.0 - 20.0 * ( c - 20 ) / 360.0 + 150.0 ) - 0.5 );
  const BandSupport wedge = bandSupport( tiles, strip, roads() ), road = bandSupport( tiles, { Eigen::Vector2d( 10.0, 239.5 ), Eigen::Vector2d( 390.0, 239.5 ) }, roads() );
  std::printf( "the strip: band support %.2f, widening %.2f; the road: %.2f, %.2f\n", wedge.share, wedge.widening, road.share, road.widening );
  EXPECT_GE( wedge.share, 0.9 ) << "a band all along";
  EXPECT_NEAR( wedge.widening, 3.5, 0.7 );
  EXPECT_GE( wedge.widening, CoincidentExtractionOptions().maxBandWidening );
  EXPECT_GE( road.share, 0.95 );
  EXPECT_NEAR( road.widening, 1.0, 0.05 );
}

// Image enhancement (thesis ch. 4, §6.1): each method against its equations,
// on 8- and 16-bit, grey and RGB, globally and in a window.
#include <random>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "imageproc/enhancement.h"

using namespace geostation;

namespace
{
  cv::Mat ramp( int depth, int channels )
  {
    cv::Mat grey( 40, 64, CV_64F );
    for ( int r = 0; r < grey.rows; ++r )
      for ( int c = 0; c < grey.cols; ++c )
        grey.at<double>( r, c ) = 40 + c + ( r % 4 ); // 40 .. 106
    const double scale = depth == CV_16U ? 257.0 : 1.0;
    cv::Mat out;
    grey.convertTo( out, depth, scale );
    if ( channels == 3 )
      cv::cvtColor( out, out, cv::COLOR_GRAY2RGB );
    return out;
  }
}

TEST( Enhancement, StretchesFollowTheirEquations )
{
  const cv::Mat image = ramp( CV_8U, 1 );
  EnhancementOptions o;
  EnhancementSummary s;
  o.method = EnhancementMethod::LinearStretch; // eq. 4.5: [40, 106] -> [0, 255]
  cv::Mat out = enhanceImage( image, o, &s );
  EXPECT_EQ( s.min, 40 );
  EXPECT_EQ( s.max, 106 );
  EXPECT_EQ( out.at<uint8_t>( 0, 0 ), 0 );
  EXPECT_EQ( out.at<uint8_t>( 3, 63 ), 255 );
  EXPECT_EQ( out.at<uint8_t>( 0, 33 ), std::lround( 33.0 / 66.0 * 255 ) );

  o.method = EnhancementMethod::TwoSegmentStretch; // eq. 4.6: the mean goes to pmean
  o.preferredMean = 128;
  out = enhanceImage( image, o, &s );
  const double mean = s.mean;
  EXPECT_NEAR( cv::mean( out )[0], 128, 3 );
  EXPECT_EQ( out.at<uint8_t>( 0, 0 ), 0 );
  EXPECT_EQ( out.at<uint8_t>( 3, 63 ), 255 );

  o.method = EnhancementMethod::ThreeSegmentStretch; // eq. 4.7 with a = mean, b = mean + 30, a' = 150
  out = enhanceImage( image, o, &s );
  for ( int c = 0; c < 64; ++c )
  {
    const double g = image.at<uint8_t>( 1, c );
    const double expected = g <= mean ? 150.0 / ( mean - 40 ) * ( g - 40 )
                            : g <= mean + 30 ? g - mean + 150
                            : ( 255.0 - 180.0 ) / ( 106 - mean - 30 ) * ( g - mean - 30 ) + 180.0;
    EXPECT_NEAR( out.at<uint8_t>( 1, c ), expected, 0.5 ) << c;
  }
}

TEST( Enhancement, EqualisationFlattensTheHistogram )
{
  cv::Mat image( 100, 100, CV_8U );
  cv::RNG rng( 1 );
  rng.fill( image, cv::RNG::NORMAL, 90, 10 );
  EnhancementOptions o;
  o.method = EnhancementMethod::Equalise;
  const cv::Mat out = enhanceImage( image, o );
  // the cumulative distribution becomes linear: the median moves to mid-grey
  std::vector<uint8_t> v( out.begin<uint8_t>(), out.end<uint8_t>() );
  std::nth_element( v.begin(), v.begin() + v.size() / 2, v.end() );
  EXPECT_NEAR( v[v.size() / 2], 128, 6 );
  double lo, hi;
  cv::minMaxLoc( out, &lo, &hi );
  EXPECT_EQ( hi, 255 );
}

TEST( Enhancement, SixteenBitRgbAndWindows )
{
  const cv::Mat image = ramp( CV_16U, 3 );
  EnhancementOptions o;
  o.method = EnhancementMethod::LinearStretch;
  o.window = cv::Rect( 10, 5, 20, 10 );
  const cv::Mat out = enhanceImage( image, o );
  ASSERT_EQ( out.type(), CV_16UC3 );
  // outside the window nothing changes; inside, the window's own range is stretched to the full 16 bits
  EXPECT_EQ( out.at<cv::Vec3w>( 0, 0 ), image.at<cv::Vec3w>( 0, 0 ) );
  double lo, hi;
  cv::minMaxLoc( out( *o.window ).reshape( 1 ), &lo, &hi );
  EXPECT_EQ( lo, 0 );
  EXPECT_EQ( hi, 65535 );
  const cv::Vec3w p = out.at<cv::Vec3w>( 8, 20 );
  EXPECT_EQ( p[0], p[1] ); // grey stays grey
  EXPECT_THROW( enhanceImage( cv::Mat( 4, 4, CV_32F ), o ), std::invalid_argument );
  o.window = cv::Rect( 100, 100, 5, 5 );
  EXPECT_THROW( enhanceImage( image, o ), std::invalid_argument );
}

TEST( Enhancement, AddBackSharpensEdgesOnly )
{
  cv::Mat step( 20, 20, CV_8U, cv::Scalar( 80 ) );
  step( cv::Rect( 10, 0, 10, 20 ) ).setTo( 160 );
  for ( EnhancementMethod m : { EnhancementMethod::SobelAddBack, EnhancementMethod::DifferenceAddBack } )
  {
    EnhancementOptions o;
    o.method = m;
    o.scale = 0.5;
    o.threshold = 20;
    EnhancementSummary s;
    const cv::Mat out = enhanceImage( step, o, &s );
    EXPECT_EQ( out.at<uint8_t>( 10, 2 ), 80 ) << enhancementMethodName( m ); // flat: unchanged
    EXPECT_EQ( out.at<uint8_t>( 10, 17 ), 160 );
    EXPECT_GT( s.changedPixels, 0 );
    EXPECT_LE( s.changedPixels, 20 * 4 ); // only along the edge
  }
  // the grey-level difference (eq. 4.15): the bright side of the edge gets brighter by scale * 80
  EnhancementOptions d;
  d.method = EnhancementMethod::DifferenceAddBack;
  EXPECT_EQ( enhanceImage( step, d ).at<uint8_t>( 10, 10 ), 200 );
}

TEST( Enhancement, BoxFilterRemovesBitErrorsButKeepsEdges )
{
  cv::Mat image( 60, 60, CV_8U );
  for ( int r = 0; r < 60; ++r )
    for ( int c = 0; c < 60; ++c )
      image.at<uint8_t>( r, c ) = static_cast<uint8_t>( c < 30 ? 70 + ( r + c ) % 5 : 170 + ( r * c ) % 5 );
  cv::Mat noisy = image.clone();
  std::mt19937 random( 2 );
  std::uniform_int_distribution<int> u( 2, 57 );
  std::vector<cv::Point> hits;
  for ( int k = 0; k < 40; ++k )
  {
    const cv::Point p( u( random ), u( random ) );
    noisy.at<uint8_t>( p ) = k % 2 ? 255 : 0;
    hits.push_back( p );
  }
  EnhancementOptions o;
  o.method = EnhancementMethod::AdaptiveBoxFilter;
  const cv::Mat out = enhanceImage( noisy, o );
  // away from the edge (where the box's contrast is high on purpose) every bit error goes
  int away = 0, repaired = 0;
  for ( const cv::Point &p : hits )
    if ( std::abs( p.x - 29.5 ) > 4 )
    {
      ++away;
      repaired += std::abs( out.at<uint8_t>( p ) - image.at<uint8_t>( p ) ) < 15 ? 1 : 0;
    }
  EXPECT_GE( repaired, away - 1 ) << "of " << away;
  // the edge between the halves survives
  EXPECT_LT( out.at<uint8_t>( 20, 29 ), 90 );
  EXPECT_GT( out.at<uint8_t>( 20, 30 ), 150 );
}

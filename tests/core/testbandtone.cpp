// A band's tone (crossprofile.h, linestate.h): with either polarity, a band
// is brighter than both sides, darker than both, or between a darker and a
// brighter side. A line followed by LEM (localextraction.h) does not pass
// from a band of one tone to one of the other in a step - from the asphalt
// onto its bright shoulder, or onto any bright band beside the road where
// the road itself is hidden - but goes on where a road passes from a
// bright field into a dark wood through a stretch between the two.
#include <gtest/gtest.h>

#include <algorithm>

#include <opencv2/imgproc.hpp>

#include "extraction/crossprofile.h"
#include "extraction/localextraction.h"
#include "extraction/resultmatrix.h"

using namespace geostation;

namespace
{
  //! Rows top..top+height-1 of columns from..to-1 painted `grey`.
  void paint( cv::Mat &image, int top, int height, int from, int to, int grey )
  {
    image( cv::Rect( from, top, to - from, height ) ).setTo( grey );
  }

  LineObjectOptions eitherPolarity()
  {
    LineObjectOptions object;
    object.polarity = 0;
    object.minWidthPx = 6.0;
    object.maxWidthPx = 20.0;
    object.minContrast = 20.0;
    return object;
  }

  //! LEM from (20, 56) to the right along a band 12 px wide of the given tone.
  LemSummary followFromTheLeft( const cv::Mat &image, int tone )
  {
    LineState start;
    start.pixelInImage = Eigen::Vector2d( 20.0, 56.0 );
    start.direction = Eigen::Vector2d::UnitX();
    start.widthPx = 12.0;
    start.contrast = 50.0;
    start.tone = tone;
    const ResultMatrix matrix( image.cols, image.rows );
    return followLocally( image, matrix, start, eitherPolarity(), LemOptions() );
  }
} // namespace

TEST( BandTone, ACrossSectionSaysWhetherItsBandIsBrighterDarkerOrBetween )
{
  // a profile of 120 samples: a dark band, a bright band and a band between a dark and a bright side
  std::vector<double> profile( 120, 110.0 );
  std::fill( profile.begin() + 10, profile.begin() + 22, 60.0 );  // dark on grass
  std::fill( profile.begin() + 45, profile.begin() + 57, 190.0 ); // bright on grass
  std::fill( profile.begin() + 80, profile.begin() + 92, 150.0 ); // between grass (110) and a bright field
  std::fill( profile.begin() + 92, profile.end(), 200.0 );
  const std::vector<CrossSection> sections = findCrossSections( profile, 8.0, 16.0, 20.0, 14.0, false, 0 );
  const auto toneAt = [&]( double centre ) {
    for ( const CrossSection &s : sections )
      if ( std::abs( s.offsetPx + 59.5 - centre ) < 2.0 )
        return s.tone;
    return 99;
  };
  EXPECT_EQ( toneAt( 15.5 ), -1 );
  EXPECT_EQ( toneAt( 50.5 ), 1 );
  EXPECT_EQ( toneAt( 85.5 ), 0 );
  // a fixed polarity: the tone is the polarity's
  for ( const CrossSection &s : findCrossSections( profile, 8.0, 16.0, 20.0, 14.0, false, 1 ) )
    EXPECT_EQ( s.tone, 1 );
}

TEST( BandTone, ALineOnTheAsphaltDoesNotStepOntoABrightBandBesideIt )
{
  // grass 110; dark asphalt (rows 50-61, grey 60) up to column 150, where the road is hidden and a bright band
  // of its width runs on 4 px lower (rows 54-65, grey 190): within a step's search, of the line's width
  cv::Mat image( 120, 300, CV_8U, cv::Scalar( 110 ) );
  paint( image, 50, 12, 0, 150, 60 );
  paint( image, 54, 12, 150, 300, 190 );
  const LemSummary dark = followFromTheLeft( image, -1 );
  EXPECT_LT( dark.end.pixelInImage.x(), 150.0 + 2.0 * 12.0 + 12.0 ) << "through the junction's mouth at most";
  for ( const Eigen::Vector2d &p : dark.pixels )
    EXPECT_LT( p.y(), 58.5 ) << "onto the bright band at " << p.x();
  // a start whose tone is not known (a stretch between) may go on either way
  const LemSummary unknown = followFromTheLeft( image, 0 );
  EXPECT_GT( unknown.steps, 0 );
}

TEST( BandTone, ALineGoesOnFromDarkToBrightThroughAStretchBetween )
{
  // a road of grey 100 (rows 50-61) between bright fields (160), then a dark wood (40) above it from column 100,
  // below it too from column 200: darker than both sides, between, brighter than both
  cv::Mat image( 120, 300, CV_8U, cv::Scalar( 160 ) );
  paint( image, 0, 50, 100, 300, 40 );
  paint( image, 62, 58, 200, 300, 40 );
  paint( image, 50, 12, 0, 300, 100 );
  const LemSummary line = followFromTheLeft( image, -1 );
  EXPECT_EQ( line.stop, DeadEndKind::ImageBorder );
  EXPECT_GT( line.end.pixelInImage.x(), 270.0 );
  EXPECT_EQ( line.end.tone, 1 );
  for ( const Eigen::Vector2d &p : line.pixels )
    EXPECT_NEAR( p.y(), 56.0, 1.0 );
}

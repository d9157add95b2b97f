/***************************************************************************
  testheightcontinuity.cpp - vertices that leave the road's height along a line
 ***************************************************************************/
#include <random>
#include <set>

#include <gtest/gtest.h>

#include "tracing/heightcontinuity.h"

using namespace geostation;

namespace
{
  //! A road line 80 m long through a curve, on a 4 % grade easing into a crest; vertices every metre,
  //! each station's 10 m shifted in height by its own pose error (3 cm) and each vertex by 1.2 cm more.
  struct GradedLine
  {
    std::vector<Eigen::Vector3d> points;
    std::vector<double> sigmaZ;

    GradedLine()
    {
      std::mt19937 random( 11 );
      std::normal_distribution<double> pose( 0.0, 0.03 ), vertex( 0.0, 0.012 );
      double stationError = 0.0;
      for ( int i = 0; i < 80; ++i )
      {
        if ( i % 10 == 0 )
          stationError = pose( random );
        const double s = i;
        const double angle = s / 60.0; // a 60 m radius curve
        const double z = 100.0 + 0.04 * s - 0.0004 * s * s;
        points.emplace_back( 60.0 * std::sin( angle ), 60.0 * ( 1.0 - std::cos( angle ) ), z + stationError + vertex( random ) );
        sigmaZ.push_back( 0.035 );
      }
    }
  };
}

TEST( HeightContinuity, FlagsWrongHeightsAndNothingElse )
{
  GradedLine line;
  // nothing flagged on the clean line: grade, crest, curve and pose steps between stations are the road's
  EXPECT_TRUE( heightOutliers( line.points, line.sigmaZ, 0 ).empty() );

  // wrong conjugates: 22 cm low, 15 cm high, and two neighbours 30 cm high
  const std::set<size_t> wrong { 17, 40, 60, 61 };
  line.points[17].z() -= 0.22;
  line.points[40].z() += 0.15;
  line.points[60].z() += 0.30;
  line.points[61].z() += 0.30;
  const std::vector<size_t> flagged = heightOutliers( line.points, line.sigmaZ, 0 );
  EXPECT_EQ( std::set<size_t>( flagged.begin(), flagged.end() ), wrong );

  // only those from `firstChecked` on are looked at
  const std::vector<size_t> late = heightOutliers( line.points, line.sigmaZ, 50 );
  EXPECT_EQ( std::set<size_t>( late.begin(), late.end() ), ( std::set<size_t> { 60, 61 } ) );

  // 6 cm is within what the sigmas and minStepM allow
  GradedLine small;
  small.points[30].z() += 0.06;
  EXPECT_TRUE( heightOutliers( small.points, small.sigmaZ, 0 ).empty() );
}

TEST( HeightContinuity, TooFewNeighboursAndBadInput )
{
  GradedLine line;
  std::vector<Eigen::Vector3d> few( line.points.begin(), line.points.begin() + 4 );
  std::vector<double> fewSigma( line.sigmaZ.begin(), line.sigmaZ.begin() + 4 );
  few[2].z() += 0.5;
  EXPECT_TRUE( heightOutliers( few, fewSigma, 0 ).empty() ); // 3 neighbours: not judged
  HeightContinuityOptions one;
  one.minNeighbours = 1; // a single neighbour gives no line: not judged, whatever the option says
  EXPECT_TRUE( heightOutliers( std::vector<Eigen::Vector3d>( few.begin(), few.begin() + 2 ), std::vector<double>( 2, 0.03 ), 0, one ).empty() );
  fewSigma.pop_back();
  EXPECT_THROW( heightOutliers( few, fewSigma, 0 ), std::invalid_argument );
}

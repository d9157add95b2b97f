/***************************************************************************
  proceduralroads.cpp - the roads of the procedural scenes
 ***************************************************************************/
#include "simulation/proceduralroads.h"

#include <algorithm>
#include <cmath>

#include "geometry/rotation.h"

namespace geostation
{
  namespace
  {
    //! Arc of radius r turning by `turnRad` (positive left) from `start` heading `heading`, 2 m vertices.
    void appendArc( std::vector<Eigen::Vector2d> &line, double &heading, double radius, double turnRad )
    {
      const Eigen::Vector2d start = line.back();
      const double side = turnRad > 0 ? 1.0 : -1.0;
      const Eigen::Vector2d centre = start + side * radius * Eigen::Vector2d( -std::sin( heading ), std::cos( heading ) );
      const int n = std::max( 2, static_cast<int>( std::abs( turnRad ) * radius / 2.0 ) );
      const double a0 = heading - side * kPi / 2;
      for ( int k = 1; k <= n; ++k )
      {
        const double a = a0 + turnRad * k / n;
        line.push_back( centre + radius * Eigen::Vector2d( std::cos( a ), std::sin( a ) ) );
      }
      heading += turnRad;
    }

    void appendStraight( std::vector<Eigen::Vector2d> &line, double heading, double length )
    {
      line.push_back( line.back() + length * Eigen::Vector2d( std::cos( heading ), std::sin( heading ) ) );
    }
  } // namespace

  std::vector<Road> proceduralRoads( SurveyPreset preset, const Eigen::Vector2d &centre )
  {
    std::vector<Road> roads;
    Road main;
    main.id = "R1";
    Road side;
    side.id = "R2";
    side.dashedCentre = true;
    side.laneWidthM = 3.25;
    double heading = 0.0;
    switch ( preset )
    {
      case SurveyPreset::Highway:
      {
        main.lanesPerDirection = 2;
        main.laneWidthM = 3.5;
        main.centreline = { centre + Eigen::Vector2d( -60, 0 ) };
        appendStraight( main.centreline, heading, 160 );
        appendArc( main.centreline, heading, 220, degToRad( 30 ) );
        appendStraight( main.centreline, heading, 200 );
        appendArc( main.centreline, heading, 300, degToRad( -20 ) );
        appendStraight( main.centreline, heading, 400 );
        side.centreline = { centre + Eigen::Vector2d( 45, 0 ), centre + Eigen::Vector2d( 45, 260 ) };
        break;
      }
      case SurveyPreset::AerialStereo:
      case SurveyPreset::ObliquePhoto:
      {
        main.lanesPerDirection = 1;
        main.centreline = { centre + Eigen::Vector2d( -700, -40 ) };
        appendStraight( main.centreline, heading, 620 );
        appendArc( main.centreline, heading, 160, degToRad( 25 ) );
        appendStraight( main.centreline, heading, 120 );
        appendArc( main.centreline, heading, 160, degToRad( -25 ) );
        appendStraight( main.centreline, heading, 700 );
        side.centreline = { centre + Eigen::Vector2d( -20, -28 ), centre + Eigen::Vector2d( -20, -700 ) };
        Road third;
        third.id = "R3";
        third.dashedCentre = true;
        third.laneWidthM = 3.0;
        double h3 = kPi / 2;
        // leaves the main road northwards and bends
        third.centreline = { centre + Eigen::Vector2d( 40, 0 ) };
        appendStraight( third.centreline, h3, 90 );
        appendArc( third.centreline, h3, 120, degToRad( -40 ) );
        appendStraight( third.centreline, h3, 600 );
        roads.push_back( main );
        roads.push_back( side );
        roads.push_back( third );
        return roads;
      }
    }
    roads.push_back( main );
    roads.push_back( side );
    return roads;
  }

} // namespace geostation

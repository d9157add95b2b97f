/***************************************************************************
  threepointpose.cpp - a camera's pose from three rays (P3P)
 ***************************************************************************/
#include "identification/threepointpose.h"

#include <opencv2/calib3d.hpp>

namespace geostation
{

  std::vector<ThreePointPose> threePointPoses( const std::array<Eigen::Vector3d, 3> &world, const std::array<Eigen::Vector2d, 3> &ideal )
  {
    cv::Mat objectPoints( 3, 3, CV_64F ), imagePoints( 3, 2, CV_64F );
    for ( int k = 0; k < 3; ++k )
    {
      for ( int a = 0; a < 3; ++a )
        objectPoints.at<double>( k, a ) = world[k][a];
      imagePoints.at<double>( k, 0 ) = ideal[k].x();
      imagePoints.at<double>( k, 1 ) = -ideal[k].y(); // OpenCV: y down, z forward
    }
    std::vector<cv::Mat> rvecs, tvecs;
    int solutions = 0;
    try
    {
      solutions = cv::solveP3P( objectPoints, imagePoints, cv::Matx33d::eye(), cv::noArray(), rvecs, tvecs, cv::SOLVEPNP_AP3P );
    }
    catch ( const cv::Exception & )
    {
      return {};
    }
    std::vector<ThreePointPose> poses;
    const Eigen::Matrix3d flip = Eigen::Vector3d( 1, -1, -1 ).asDiagonal(); // ours: x right, y up, z back
    for ( int s = 0; s < solutions; ++s )
    {
      cv::Matx33d rotation;
      cv::Rodrigues( rvecs[s], rotation );
      Eigen::Matrix3d cvFromWorld;
      for ( int r = 0; r < 3; ++r )
        for ( int c = 0; c < 3; ++c )
          cvFromWorld( r, c ) = rotation( r, c );
      const Eigen::Vector3d t( tvecs[s].at<double>( 0 ), tvecs[s].at<double>( 1 ), tvecs[s].at<double>( 2 ) );
      ThreePointPose pose;
      pose.cameraFromWorld = flip * cvFromWorld;
      pose.centre = -cvFromWorld.transpose() * t;
      if ( !pose.cameraFromWorld.allFinite() || !pose.centre.allFinite() )
        continue;
      bool inFront = true;
      for ( int k = 0; k < 3 && inFront; ++k )
        inFront = ( pose.cameraFromWorld * ( world[k] - pose.centre ) ).z() < 0.0;
      if ( inFront )
        poses.push_back( pose );
    }
    return poses;
  }

} // namespace geostation

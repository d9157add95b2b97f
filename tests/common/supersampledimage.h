// A small test image painted from a function of the image plane, its edges
// at sub-pixel positions: each pixel the mean of 4 x 4 sub-samples, then
// noise. For tests that place a band's borders (a road, its shoulders) to
// a fraction of a pixel and check where a line ends up.
#ifndef GEOSTATION_TESTS_SUPERSAMPLEDIMAGE_H
#define GEOSTATION_TESTS_SUPERSAMPLEDIMAGE_H

#include <functional>
#include <random>

#include <opencv2/core.hpp>

namespace geostation
{
  /**
   * A 300 x 200 image of `value`( x, y ) (pixelInImage: pixel (col, row) covers [col, col + 1), its centre is
   * col + 0.5), averaged over 4 x 4 sub-samples for the edges, with noise of 3 grey levels drawn from `seed`.
   */
  inline cv::Mat supersampled( unsigned seed, const std::function<double( double, double )> &value )
  {
    cv::Mat grey( 200, 300, CV_8U );
    std::mt19937 random( seed );
    std::normal_distribution<double> noise( 0.0, 3.0 );
    for ( int row = 0; row < grey.rows; ++row )
      for ( int col = 0; col < grey.cols; ++col )
      {
        double sum = 0.0;
        for ( int i = 0; i < 4; ++i )
          for ( int j = 0; j < 4; ++j )
            sum += value( col + ( i + 0.5 ) / 4.0, row + ( j + 0.5 ) / 4.0 );
        grey.at<uint8_t>( row, col ) = cv::saturate_cast<uint8_t>( sum / 16.0 + noise( random ) );
      }
    return grey;
  }
} // namespace geostation

#endif // GEOSTATION_TESTS_SUPERSAMPLEDIMAGE_H

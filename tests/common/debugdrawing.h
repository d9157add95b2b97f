// Pictures for a developer looking at what a test extracted: with
// GEOSTATION_EXTRACTION_DEBUG set to a folder, a grey image with sets of
// lines drawn on it, each in its colour, written there as <name>.png;
// nothing without it.
#ifndef GEOSTATION_TESTS_DEBUGDRAWING_H
#define GEOSTATION_TESTS_DEBUGDRAWING_H

#include <cstdlib>
#include <string>
#include <utility>
#include <vector>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "imagelinescoring.h"

namespace geostation
{
  //! `grey` with each set of lines (pixelInImage) in its colour (BGR), as GEOSTATION_EXTRACTION_DEBUG/<name>.png.
  inline void drawLinesForDebugging( const std::string &name, const cv::Mat &grey, const std::vector<std::pair<std::vector<PixelPolyline>, cv::Scalar>> &sets )
  {
    const char *out = std::getenv( "GEOSTATION_EXTRACTION_DEBUG" );
    if ( !out )
      return;
    cv::Mat canvas;
    cv::cvtColor( grey, canvas, cv::COLOR_GRAY2BGR );
    for ( const auto &[lines, colour] : sets )
      for ( const PixelPolyline &l : lines )
        for ( size_t i = 0; i + 1 < l.size(); ++i )
          cv::line( canvas, cv::Point2d( l[i].x() - 0.5, l[i].y() - 0.5 ), cv::Point2d( l[i + 1].x() - 0.5, l[i + 1].y() - 0.5 ), colour, 1 );
    cv::imwrite( std::string( out ) + "/" + name + ".png", canvas );
  }
} // namespace geostation

#endif // GEOSTATION_TESTS_DEBUGDRAWING_H

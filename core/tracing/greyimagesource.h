/***************************************************************************
  greyimagesource.h - block images as 8-bit grey, for tracing
  -------------------------------------------------------------------------
  Tracing reads the images of each station it passes, the same images
  again at the next stations (a station's images serve the stations
  behind and ahead of it), from several threads at once when several
  lines are traced side by side. A GreyImageSource hands out an image's
  8-bit grey levels shared and read once; fileGreyImageSource() reads
  them with GDAL and keeps the last few.
 ***************************************************************************/
#ifndef GEOSTATION_TRACING_GREYIMAGESOURCE_H
#define GEOSTATION_TRACING_GREYIMAGESOURCE_H

#include <functional>
#include <memory>
#include <string>

#include <opencv2/core.hpp>

#include "io/block.h"

namespace geostation
{

  /**
   * The 8-bit grey image of a block image; nullptr and `error` (one
   * sentence) when it cannot be read.
   */
  using GreyImageSource = std::function<std::shared_ptr<const cv::Mat>( const BlockImage &, std::string &error )>;

  //! Reads block images with GDAL and keeps the last `capacity` in memory (thread-safe). The block is referenced: keep it alive.
  GreyImageSource fileGreyImageSource( const Block &block, size_t capacity = 6 );

} // namespace geostation

#endif // GEOSTATION_TRACING_GREYIMAGESOURCE_H

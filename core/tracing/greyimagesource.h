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

  //! A block image's 8-bit grey levels, or why there are none.
  struct GreyImage
  {
    enum class Status
    {
      Ready,
      Unreadable, //!< the file cannot be opened or decoded
      WrongSize,  //!< its size is not its camera's
    };
    Status status = Status::Ready;
    std::string message;                  //!< one sentence when not Ready
    std::shared_ptr<const cv::Mat> grey;  //!< CV_8UC1 when Ready, else null
    bool ok() const { return status == Status::Ready; }
  };

  //! The grey image of a block image (shared: the same pixels for every caller).
  using GreyImageSource = std::function<GreyImage( const BlockImage & )>;

  //! Reads block images with GDAL and keeps the last `capacity` in memory (thread-safe). The block is referenced: keep it alive.
  GreyImageSource fileGreyImageSource( const Block &block, size_t capacity = 6 );

} // namespace geostation

#endif // GEOSTATION_TRACING_GREYIMAGESOURCE_H

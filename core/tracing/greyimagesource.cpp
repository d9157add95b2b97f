/***************************************************************************
  greyimagesource.cpp - block images as 8-bit grey, for tracing
 ***************************************************************************/
#include "tracing/greyimagesource.h"

#include <list>
#include <mutex>

#include <opencv2/imgproc.hpp>

#include "io/rasterfile.h"

namespace geostation
{

  GreyImageSource fileGreyImageSource( const Block &block, size_t capacity )
  {
    struct Cache
    {
      std::mutex mutex;
      std::list<std::pair<std::string, std::shared_ptr<const cv::Mat>>> entries;
    };
    auto cache = std::make_shared<Cache>();
    const auto failed = []( GreyImage::Status status, const std::string &message ) {
      GreyImage out;
      out.status = status;
      out.message = message;
      return out;
    };
    return [cache, capacity, &block, failed]( const BlockImage &image ) -> GreyImage
    {
      const std::string path = block.imageFilePath( image ).string();
      {
        std::lock_guard<std::mutex> lock( cache->mutex );
        for ( const auto &e : cache->entries )
          if ( e.first == path )
            return GreyImage { GreyImage::Status::Ready, std::string(), e.second };
      }
      try
      {
        const cv::Mat pixels = readRaster( path ).pixels;
        auto grey = std::make_shared<cv::Mat>();
        cv::Mat eight = pixels;
        if ( pixels.depth() == CV_16U )
        {
          double lo, hi;
          cv::minMaxLoc( pixels.reshape( 1 ), &lo, &hi );
          pixels.convertTo( eight, CV_8U, hi > lo ? 255.0 / ( hi - lo ) : 1.0, hi > lo ? -lo * 255.0 / ( hi - lo ) : 0.0 );
        }
        if ( eight.channels() == 3 )
          cv::cvtColor( eight, *grey, cv::COLOR_RGB2GRAY );
        else
          *grey = eight;
        const Camera *camera = block.findCamera( image.cameraId );
        if ( camera && ( grey->cols != camera->width || grey->rows != camera->height ) )
        {
          return failed( GreyImage::Status::WrongSize, "the image " + image.id + " is " + std::to_string( grey->cols ) + " x " + std::to_string( grey->rows ) +
                         " px but its camera " + camera->id + " is " + std::to_string( camera->width ) + " x " + std::to_string( camera->height ) );
        }
        std::lock_guard<std::mutex> lock( cache->mutex );
        cache->entries.push_front( { path, grey } );
        if ( cache->entries.size() > capacity )
          cache->entries.pop_back();
        return GreyImage { GreyImage::Status::Ready, std::string(), grey };
      }
      catch ( const std::exception &e )
      {
        return failed( GreyImage::Status::Unreadable, "the image " + image.id + " cannot be read: " + e.what() );
      }
    };
  }

} // namespace geostation

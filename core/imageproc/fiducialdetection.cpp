/***************************************************************************
  fiducialdetection.cpp - automatic location of fiducial marks in a scan
 ***************************************************************************/
#include "imageproc/fiducialdetection.h"

#include <cmath>
#include <memory>
#include <stdexcept>

#include <cpl_error.h>
#include <gdal.h>
#include <opencv2/imgproc.hpp>

namespace geostation
{

  namespace
  {
    struct DatasetCloser
    {
      void operator()( void *ds ) const { GDALClose( ds ); }
    };

    //! Reads a window of band 1 as 8-bit (linearly scaled for 16-bit), optionally subsampled by GDAL.
    cv::Mat readWindow( GDALDatasetH ds, const cv::Rect &window, int factor )
    {
      const int w = std::max( 1, window.width / factor ), h = std::max( 1, window.height / factor );
      cv::Mat buffer( h, w, CV_32F );
      GDALRasterIOExtraArg extra;
      INIT_RASTERIO_EXTRA_ARG( extra );
      extra.eResampleAlg = factor > 1 ? GRIORA_Average : GRIORA_NearestNeighbour;
      if ( GDALRasterIOEx( GDALGetRasterBand( ds, 1 ), GF_Read, window.x, window.y, window.width, window.height, buffer.data, w, h, GDT_Float32, 0, 0, &extra ) != CE_None )
        throw std::runtime_error( std::string( "cannot read the image: " ) + CPLGetLastErrorMsg() );
      return buffer;
    }

    cv::Mat genericDisc( double diameterPx, bool bright )
    {
      const int size = static_cast<int>( std::ceil( diameterPx * 2.0 ) ) | 1;
      cv::Mat mark( size, size, CV_32F );
      const double c = size / 2.0, r = diameterPx / 2.0;
      // 4 x 4 supersampled coverage of the disc.
      for ( int y = 0; y < size; ++y )
        for ( int x = 0; x < size; ++x )
        {
          int inside = 0;
          for ( int sy = 0; sy < 4; ++sy )
            for ( int sx = 0; sx < 4; ++sx )
              inside += std::hypot( x + ( sx + 0.5 ) / 4 - c, y + ( sy + 0.5 ) / 4 - c ) <= r ? 1 : 0;
          const float coverage = inside / 16.0f;
          mark.at<float>( y, x ) = bright ? coverage : 1.0f - coverage;
        }
      return mark;
    }

    /**
     * Centre of gravity of the mark in a full-resolution patch. The mark is
     * found as the pixels whose excess over the background (the patch median),
     * with the mark's sign, exceeds three times the background noise or a
     * quarter of the mark's contrast; that region is grown by two pixels so
     * the partly covered edge pixels count fully, and within it every pixel
     * weighs its excess linearly. A weight linear in coverage keeps the
     * centroid of an anti-aliased mark unbiased.
     */
    std::optional<Eigen::Vector2d> centreOfGravity( const cv::Mat &patch, bool bright )
    {
      std::vector<float> values( patch.begin<float>(), patch.end<float>() );
      std::nth_element( values.begin(), values.begin() + values.size() / 2, values.end() );
      const float background = values[values.size() / 2];
      cv::Mat excess = ( bright ? 1.0 : -1.0 ) * ( patch - background );
      std::vector<float> deviations;
      deviations.reserve( values.size() );
      for ( float v : values )
        deviations.push_back( std::abs( v - background ) );
      std::nth_element( deviations.begin(), deviations.begin() + deviations.size() / 2, deviations.end() );
      const double noise = 1.4826 * deviations[deviations.size() / 2];
      double peak = 0.0;
      cv::minMaxLoc( excess, nullptr, &peak );
      // above the noise, but never above half the peak: a textured background must not hide the mark itself
      const double threshold = std::min( std::max( 3.0 * noise, 0.25 * peak ), 0.5 * peak );
      cv::Mat mask = excess > threshold;
      if ( cv::countNonZero( mask ) == 0 )
        return std::nullopt;
      cv::dilate( mask, mask, cv::Mat(), cv::Point( -1, -1 ), 2 );
      double sum = 0.0, sumX = 0.0, sumY = 0.0;
      for ( int y = 0; y < patch.rows; ++y )
        for ( int x = 0; x < patch.cols; ++x )
        {
          if ( !mask.at<unsigned char>( y, x ) )
            continue;
          const double weight = std::max( 0.0f, excess.at<float>( y, x ) );
          sum += weight;
          sumX += weight * ( x + 0.5 );
          sumY += weight * ( y + 0.5 );
        }
      if ( !( sum > 0.0 ) )
        return std::nullopt;
      return Eigen::Vector2d( sumX / sum, sumY / sum );
    }
  } // namespace

  std::array<DetectedFiducial, 4> detectCornerFiducials( const std::string &imagePath, const FiducialDetectionOptions &options )
  {
    if ( !( options.scanPixelMm > 0.0 ) )
      throw std::invalid_argument( "fiducial detection needs the scan resolution (pixel size in mm)" );
    if ( options.markTemplate.empty() && !( options.markDiameterPx > 2.0 ) )
      throw std::invalid_argument( "fiducial detection needs a mark template or a mark diameter above 2 pixels" );

    GDALAllRegister();
    CPLPushErrorHandler( CPLQuietErrorHandler );
    std::unique_ptr<void, DatasetCloser> ds( GDALOpenEx( imagePath.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY, nullptr, nullptr, nullptr ) );
    CPLPopErrorHandler();
    if ( !ds )
      throw std::runtime_error( "cannot open the image " + imagePath );
    const int width = GDALGetRasterXSize( ds.get() ), height = GDALGetRasterYSize( ds.get() );

    // The paper: corner windows of 51.2 mm, subsampled to 0.1 mm pixels.
    const int windowSize = std::min( static_cast<int>( std::lround( 51.2 / options.scanPixelMm ) ), std::min( width, height ) / 2 );
    const int factor = std::max( 1, static_cast<int>( std::lround( 0.1 / options.scanPixelMm ) ) );

    cv::Mat fullTemplate;
    bool bright = options.brightMark;
    if ( options.markTemplate.empty() )
      fullTemplate = genericDisc( options.markDiameterPx, options.brightMark );
    else
    {
      options.markTemplate.convertTo( fullTemplate, CV_32F );
      // A template's polarity: is the centre brighter than its border?
      const cv::Scalar border = ( cv::mean( fullTemplate.row( 0 ) ) + cv::mean( fullTemplate.row( fullTemplate.rows - 1 ) ) ) * 0.5;
      bright = fullTemplate.at<float>( fullTemplate.rows / 2, fullTemplate.cols / 2 ) >= border[0];
    }
    cv::Mat smallTemplate;
    cv::resize( fullTemplate, smallTemplate, cv::Size( std::max( 3, fullTemplate.cols / factor ), std::max( 3, fullTemplate.rows / factor ) ), 0, 0, cv::INTER_AREA );

    std::array<DetectedFiducial, 4> result;
    const cv::Rect windows[4] = { { 0, 0, windowSize, windowSize }, { width - windowSize, 0, windowSize, windowSize },
      { width - windowSize, height - windowSize, windowSize, windowSize }, { 0, height - windowSize, windowSize, windowSize }
    };
    for ( int k = 0; k < 4; ++k )
    {
      DetectedFiducial &d = result[k];
      d.corner = static_cast<Corner>( k );
      if ( !options.progress.report( k / 4.0, "corner " + std::to_string( k + 1 ) + " of 4" ) )
      {
        d.status = DetectedFiducial::Status::Cancelled;
        d.message = "not looked for: cancelled";
        continue;
      }
      const cv::Mat window = readWindow( ds.get(), windows[k], factor );
      if ( window.cols < smallTemplate.cols || window.rows < smallTemplate.rows )
      {
        d.status = DetectedFiducial::Status::WindowTooSmall;
        d.message = "the corner window is smaller than the mark";
        continue;
      }
      cv::Mat response;
      cv::matchTemplate( window, smallTemplate, response, cv::TM_CCOEFF_NORMED );
      double best = 0.0;
      cv::Point at;
      cv::minMaxLoc( response, nullptr, &best, nullptr, &at );
      d.score = best;
      if ( !( best >= options.minScore ) )
      {
        d.status = DetectedFiducial::Status::NoMark;
        d.message = "no mark in the corner window (best correlation " + std::to_string( best ).substr( 0, 4 ) + ")";
        continue;
      }
      // Approximate centre at full resolution, then a full-resolution patch of twice the mark's size.
      const double scaleX = static_cast<double>( windows[k].width ) / window.cols, scaleY = static_cast<double>( windows[k].height ) / window.rows;
      const Eigen::Vector2d approx( windows[k].x + ( at.x + smallTemplate.cols / 2.0 ) * scaleX, windows[k].y + ( at.y + smallTemplate.rows / 2.0 ) * scaleY );
      // Centre of gravity in a patch of the template's size plus a margin,
      // recentred on the result so the patch ends up symmetric about the mark.
      const int half = std::max( fullTemplate.cols, fullTemplate.rows ) / 2 + 2 * factor + 3;
      Eigen::Vector2d centre = approx;
      bool located = true;
      for ( int iteration = 0; iteration < 3 && located; ++iteration )
      {
        cv::Rect patch( static_cast<int>( std::lround( centre.x() ) ) - half, static_cast<int>( std::lround( centre.y() ) ) - half, 2 * half, 2 * half );
        patch &= cv::Rect( 0, 0, width, height );
        const std::optional<Eigen::Vector2d> inPatch = centreOfGravity( readWindow( ds.get(), patch, 1 ), bright );
        located = inPatch.has_value();
        if ( located )
          centre = Eigen::Vector2d( patch.x, patch.y ) + *inPatch;
      }
      if ( !located )
      {
        d.status = DetectedFiducial::Status::NoContrast;
        d.message = "the mark near (" + std::to_string( static_cast<int>( approx.x() ) ) + ", " + std::to_string( static_cast<int>( approx.y() ) ) +
                   ") has no contrast against its background";
        continue;
      }
      d.pixelInImage = centre;
      d.status = DetectedFiducial::Status::Found;
    }
    return result;
  }

  std::array<std::string, 4> cornerFiducialIds( const std::vector<Fiducial> &fiducials )
  {
    // Photo quadrants of the image corners (x right, y up): TL (-, +), TR (+, +), BR (+, -), BL (-, -).
    const int signX[4] = { -1, 1, 1, -1 }, signY[4] = { 1, 1, -1, -1 };
    std::array<std::string, 4> ids;
    std::array<double, 4> farthest { -1, -1, -1, -1 };
    for ( const Fiducial &f : fiducials )
      for ( int k = 0; k < 4; ++k )
        if ( f.photoMm.x() * signX[k] > 0.0 && f.photoMm.y() * signY[k] > 0.0 && f.photoMm.norm() > farthest[k] )
        {
          farthest[k] = f.photoMm.norm();
          ids[k] = f.id;
        }
    return ids;
  }

} // namespace geostation

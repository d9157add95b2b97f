/***************************************************************************
  rasterfile.h - images in and out of GDAL rasters, georeferencing kept
  -------------------------------------------------------------------------
  readRaster() reads a 1- or 3-band 8- or 16-bit raster into a cv::Mat
  (RGB order) with its geotransform, CRS and nodata; writeGeoTiffLike()
  writes a cv::Mat as a GeoTIFF with another raster's georeferencing,
  through a temporary file renamed into place, so a failure never leaves a
  half-written output.
 ***************************************************************************/
#ifndef GEOSTATION_IO_RASTERFILE_H
#define GEOSTATION_IO_RASTERFILE_H

#include <array>
#include <optional>
#include <string>

#include <opencv2/core.hpp>

namespace geostation
{

  struct RasterImage
  {
    cv::Mat pixels;                          //!< CV_8UC1/3 or CV_16UC1/3
    std::optional<std::array<double, 6>> geoTransform;
    std::string crsWkt;                      //!< empty without a CRS
    std::optional<double> noData;
  };

  //! Throws std::invalid_argument (unreadable, not 1 or 3 bands, not 8/16-bit) naming the file.
  RasterImage readRaster( const std::string &path );

  /**
   * Throws std::runtime_error naming the file; `like` supplies geotransform,
   * CRS and nodata (an empty RasterImage: pixel space). Images over 4 Mpx
   * get overviews (2-16), so QGIS draws them quickly. A "/vsimem/" path is
   * written directly, uncompressed (GDAL's memory files).
   */
  void writeGeoTiffLike( const std::string &path, const cv::Mat &pixels, const RasterImage &like );

  /**
   * Frees an in-memory raster written by writeGeoTiffLike() to a "/vsimem/"
   * path (written in place and uncompressed); other paths are left alone.
   */
  void discardMemoryRaster( const std::string &path );

} // namespace geostation

#endif // GEOSTATION_IO_RASTERFILE_H

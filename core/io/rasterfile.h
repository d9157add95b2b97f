/***************************************************************************
  rasterfile.h - images in and out of GDAL rasters, georeferencing kept
  -------------------------------------------------------------------------
  readRaster() reads an 8- or 16-bit grey or RGB raster into a cv::Mat
  (RGB order) with its geotransform, CRS and nodata (an alpha band is left
  out, a palette image becomes the colours of its table); writeGeoTiffLike()
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

  /**
   * Throws std::invalid_argument (unreadable, not grey or RGB with or
   * without alpha, not 8/16-bit) naming the file. The pixels are the file's
   * as stored: an EXIF orientation tag does not rotate them (the camera's
   * calibration and every pixel coordinate refer to the stored grid).
   */
  RasterImage readRaster( const std::string &path );

  /**
   * Registers GDAL's drivers, once per process (GDALAllRegister() itself
   * must not run in two threads at once). Every GDAL reader and writer here
   * calls it first.
   */
  void registerGdalDrivers();

  /**
   * The pixels `window` (raster pixels) of a raster, as readRaster() reads
   * them all; the geotransform is the whole raster's. Throws like
   * readRaster(), and if the window does not lie in the raster.
   */
  RasterImage readRasterWindow( const std::string &path, const cv::Rect &window );

  //! The raster's size in pixels; throws std::invalid_argument naming the file if it cannot be opened.
  cv::Size rasterSize( const std::string &path );

  /**
   * One raster kept open for reading window after window (readRasterWindow()
   * opens it for every window). Not thread-safe: one reader per thread.
   */
  class RasterReader
  {
    public:
      //! Throws std::invalid_argument naming the file if it cannot be opened.
      explicit RasterReader( const std::string &path );
      ~RasterReader();
      RasterReader( const RasterReader & ) = delete;
      RasterReader &operator=( const RasterReader & ) = delete;

      cv::Size size() const { return mSize; }
      //! Whether the pixels are 8-bit (else 16-bit).
      bool eightBit() const { return mEightBit; }
      //! Like readRasterWindow(); throws like it.
      RasterImage read( const cv::Rect &window ) const;

    private:
      std::string mPath;
      void *mDataset = nullptr;
      cv::Size mSize;
      bool mEightBit = true;
  };

  /**
   * Throws std::runtime_error naming the file; `like` supplies geotransform,
   * CRS and nodata (an empty RasterImage: pixel space). Images over 4 Mpx
   * get overviews (2-16), so QGIS draws them quickly. A "/vsimem/" path is
   * written directly, uncompressed (GDAL's memory files).
   */
  void writeGeoTiffLike( const std::string &path, const cv::Mat &pixels, const RasterImage &like );

  /**
   * Frees an in-memory raster written by writeGeoTiffLike() or
   * pixelSpaceSource() to a "/vsimem/" path; other paths are left alone.
   */
  void discardMemoryRaster( const std::string &path );

  /**
   * A positive EXIF number of an open GDAL dataset (GDALDatasetH) as GDAL
   * gives it ("(35)", "(4.5)" or "35"), e.g. "EXIF_FocalLength"; nothing
   * where it is absent, not a number or not positive.
   */
  std::optional<double> exifNumber( void *gdalDataset, const char *key );

  /**
   * The EXIF orientation tag of an open GDAL dataset (GDALDatasetH): 1-8,
   * 1 where it has none or a tag out of range.
   */
  int exifOrientationTag( void *gdalDataset );

  /**
   * The image file as a raster in pixel space (docs/conventions.md §1: x = col,
   * y = -row, no CRS), for a viewer that places rasters by their
   * georeferencing (QGIS): `path` itself where the file has none, else a VRT
   * written to `memoryPath` (a "/vsimem/" path) that reads the same pixels
   * with the pixel-space geotransform, no CRS, no GCPs and no RPCs - a
   * scanned photo with a world file, or a georeferenced TIFF, would otherwise
   * be drawn where its georeferencing puts it. `path` itself also where the
   * file cannot be opened or has other than 1-4 bands (the viewer says why). `exifOrientation`, if given,
   * receives the file's EXIF orientation tag from the same opening (1-8; 1
   * where it has none, or a tag out of range, or the file cannot be opened).
   * With `mirrorAsTagged`, a file tagged to be shown mirrored (2, 4, 5, 7)
   * becomes a VRT at x = -col, y = -row, which a viewer draws mirrored left
   * to right (viewForExifOrientation() gives the turn after it); the result
   * is then `memoryPath`.
   */
  std::string pixelSpaceSource( const std::string &path, const std::string &memoryPath, int *exifOrientation = nullptr, bool mirrorAsTagged = false );

} // namespace geostation

#endif // GEOSTATION_IO_RASTERFILE_H

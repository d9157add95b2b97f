/***************************************************************************
  block.h - the GeoStation block (*.geostation.json, docs/conventions.md §5)
  -------------------------------------------------------------------------
  A block is the cameras, the exposure stations and the oriented images of a
  survey, in one projected CRS. Unknown keys of the file are kept and written
  back on save.
 ***************************************************************************/
#ifndef GEOSTATION_IO_BLOCK_H
#define GEOSTATION_IO_BLOCK_H

#include <filesystem>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "camera/camera.h"
#include "geometry/exteriororientation.h"
#include "geometry/projection.h"

namespace geostation
{

  /**
   * A block file that cannot be read: names the file, the JSON path of the
   * offending value (e.g. "$.images[2].omega") and what was expected.
   */
  class BlockFormatError : public std::runtime_error
  {
    public:
      BlockFormatError( const std::string &file, const std::string &jsonPath, const std::string &problem );
      const std::string &file() const { return mFile; }
      const std::string &jsonPath() const { return mJsonPath; }
      const std::string &problem() const { return mProblem; }

    private:
      std::string mFile;
      std::string mJsonPath;
      std::string mProblem;
  };

  struct Station
  {
    std::string id;
    std::string time;       //!< ISO 8601 UTC, may be empty
    std::string trajectory; //!< P-line / run name, may be empty
    std::string extraJson = "{}"; //!< unknown keys as JSON text, kept on save
  };

  //! A scanned photo's inner orientation: pixels to photo mm (docs/conventions.md §2).
  struct ImageInnerOrientation
  {
    Eigen::Matrix<double, 2, 3> photoFromPixel = Eigen::Matrix<double, 2, 3>::Zero(); //!< photo mm = M (col, row, 1)
    double sigma0Mm = 0.0;
  };

  struct BlockImage
  {
    std::string id;
    std::string cameraId;
    std::string stationId; //!< may be empty
    std::string path;      //!< as written in the file (relative to the block file)
    std::optional<ExteriorOrientation> exterior; //!< absent until oriented
    std::optional<ImageInnerOrientation> innerOrientation; //!< scanned film, after inner orientation
    std::string extraJson = "{}"; //!< unknown keys as JSON text, kept on save
  };

  class Block
  {
    public:
      std::string crs; //!< anything PROJ reads; projected, metres
      std::vector<Camera> cameras;
      std::vector<Station> stations;
      std::vector<BlockImage> images;
      std::filesystem::path sourceFile; //!< where it was loaded from (paths are relative to it)
      std::string extraJson = "{}"; //!< unknown top-level keys as JSON text
      std::map<std::string, std::string> cameraExtraJson; //!< unknown keys per camera id, as JSON text

      //! Reads and validates a block file; throws BlockFormatError.
      static Block load( const std::filesystem::path &file );

      //! Parses block JSON text; `file` is used in messages and for relative paths.
      static Block fromJsonText( const std::string &text, const std::filesystem::path &file );

      //! The block as JSON text (2-space indent), with unknown keys put back.
      std::string toJsonText() const;

      /**
       * Writes the block atomically (temporary file, then rename), so a failed
       * save never leaves a half-written file. Relative image paths are
       * rebased onto the new file's folder. Throws std::runtime_error.
       */
      void save( const std::filesystem::path &file ) const;

      //! Throws std::invalid_argument naming the id and the ids that exist.
      const Camera &camera( const std::string &cameraId ) const;
      const BlockImage &image( const std::string &imageId ) const;
      const Camera &cameraOf( const BlockImage &image ) const { return camera( image.cameraId ); }

      const Camera *findCamera( const std::string &cameraId ) const;
      const BlockImage *findImage( const std::string &imageId ) const;
      const Station *findStation( const std::string &stationId ) const;

      //! The image's file, resolved against the block file's folder.
      std::filesystem::path imageFilePath( const BlockImage &image ) const;

      //! The exterior orientation, or std::invalid_argument if not oriented yet.
      const ExteriorOrientation &requireExterior( const BlockImage &image ) const;

      /**
       * The oriented image, with its scan affine when it has an inner
       * orientation (scanned film; see nominalFromScanAffine()). Throws like
       * requireExterior(), and std::invalid_argument when an image with an
       * inner orientation has a camera without pixel_size_mm.
       */
      OrientedImage orientedImage( const BlockImage &image ) const;
  };

  /**
   * Scanned film: the affine from scan pixels to the camera's nominal pixels.
   * The inner orientation gives photo mm = M (col, row, 1); the camera's
   * nominal pixel of photo point (x, y) is (cx + x / ps, cy - y * aspect / ps)
   * with ps its pixel_size_mm: the calibrated fiducials are in the photo
   * system whose origin is the principal point.
   */
  Eigen::Matrix<double, 2, 3> nominalFromScanAffine( const Camera &camera, const ImageInnerOrientation &innerOrientation );

  /**
   * Checks that an image's file exists, can be decoded by GDAL and has the
   * size its camera declares. Throws std::runtime_error with one sentence.
   */
  void requireReadableImageFile( const Block &block, const BlockImage &image );

} // namespace geostation

#endif // GEOSTATION_IO_BLOCK_H

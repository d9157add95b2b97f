/***************************************************************************
  photoimport.h - a single photo added to a block (Add Photo)
  -------------------------------------------------------------------------
  A photo joins an open block, or starts a new one, unoriented: its camera
  is one of the block's (same size) or a new one. A new camera comes from
  the file itself: its size, and the principal distance from the EXIF
  focal length (35 mm equivalent, or focal length and focal-plane
  resolution) when the file has it, otherwise a normal lens (the image
  diagonal, 50 mm on 35 mm film); the principal point at the centre; no
  lens distortion. A film camera comes with its calibration: principal
  distance, pixel size and fiducials (cameraFromJsonText()).
 ***************************************************************************/
#ifndef GEOSTATION_IO_PHOTOIMPORT_H
#define GEOSTATION_IO_PHOTOIMPORT_H

#include <filesystem>
#include <optional>
#include <string>

#include "camera/camera.h"
#include "io/block.h"

namespace geostation
{

  //! A camera read from a photo file.
  struct PhotoFileCamera
  {
    Camera camera;
    //! Where f comes from: "exif_35mm_equivalent", "exif_focal_plane_resolution" or "normal_lens_default".
    std::string focalSource;
    /**
     * The EXIF orientation tag (1-8; 1: shown as stored, also when there is none). GeoStation measures the
     * pixels as stored (docs/conventions.md §1); a view shows the photo turned or mirrored as
     * tagged (viewForExifOrientation()).
     */
    int exifOrientation = 1;
    //! One sentence for the operator when exifOrientation is not 1, else empty.
    std::string orientationNote() const;
  };

  /**
   * The camera of a photo file as far as the file tells it (see above).
   * Throws std::runtime_error with one sentence when the file cannot be
   * decoded as a raster.
   */
  PhotoFileCamera cameraFromPhotoFile( const std::filesystem::path &photo, const std::string &cameraId );
  //! How a view shows a photo so that it appears as its EXIF orientation tag asks, its pixels unchanged.
  struct ExifView
  {
    bool mirrored = false; //!< mirrored left to right first (the view's x = -col instead of col)
    int turnDeg = 0;       //!< then turned clockwise by 0, 90, 180 or 270 degrees
  };

  /**
   * The view of a photo tagged with EXIF orientation `tag`: 6 (a camera
   * held upright, turned right) turns 90 degrees, 3 turns 180, 8 turns 270;
   * 2 mirrors, 4 mirrors and turns 180, 5 mirrors and turns 270, 7 mirrors
   * and turns 90; 1 and anything else as stored.
   */
  ExifView viewForExifOrientation( int tag );

  /**
   * A camera written as in the block file (docs/conventions.md §5: id, width,
   * height, f, cx, cy, optional aspect, pixel_size_mm, distortion,
   * fiducials), validated as the block reader does. Throws BlockFormatError
   * naming the key.
   */
  Camera cameraFromJsonText( const std::string &json );

  //! A new, empty block in a CRS (anything PROJ reads; projected, metres), to be saved to `file`.
  Block newPhotoBlock( const std::string &crs, const std::filesystem::path &file );

  /**
   * Adds a photo, unoriented, to the block and returns its image id (the
   * file's name without extension, made unique). `camera` is used when the
   * block has a camera of its id (it must then be that camera's size), and
   * added otherwise. The path is stored relative to the block file's folder
   * when the block has one. Throws std::runtime_error when the file cannot
   * be decoded or has another size than the camera, std::invalid_argument
   * for an invalid camera.
   */
  std::string addPhotoToBlock( Block &block, const std::filesystem::path &photo, const Camera &camera );

} // namespace geostation

#endif // GEOSTATION_IO_PHOTOIMPORT_H

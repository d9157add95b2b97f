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
     * pixels as stored (CONVENTIONS §1); a view turns a photo tagged to be shown turned
     * (viewTurnForExifOrientation()) and shows one tagged to be shown mirrored as stored.
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
  /**
   * How a view turns a photo tagged with EXIF orientation `tag` so that it
   * appears as the file asks, its pixels unchanged: clockwise degrees, 90 for
   * tag 6 (a camera held upright, turned right), 180 for 3, 270 for 8, 0 for
   * 1 and anything else. Nothing for the mirrored tags (2, 4, 5, 7), which
   * no turn shows; a view shows those as stored.
   */
  std::optional<int> viewTurnForExifOrientation( int tag );

  /**
   * A camera written as in the block file (CONVENTIONS §5: id, width,
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

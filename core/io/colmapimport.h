/***************************************************************************
  colmapimport.h - a COLMAP sparse model as a GeoStation block
  -------------------------------------------------------------------------
  Cameras and poses are converted exactly (colmapconversion.h). The images
  of one COLMAP frame (from COLMAP 3.12: the images a rig of cameras took at
  one instant, a van's exposure) become one exposure station, named after
  the image of the rig's reference camera; without frames (an older COLMAP)
  every image becomes its own station. The 3-D points become tie points
  with their observations.
  Cameras GeoStation cannot represent are dropped by name with their images,
  and the summary says so.
 ***************************************************************************/
#ifndef GEOSTATION_IO_COLMAPIMPORT_H
#define GEOSTATION_IO_COLMAPIMPORT_H

#include <filesystem>
#include <string>

#include "io/blockimport.h"
#include "io/colmapmodel.h"

namespace geostation
{

  struct ColmapImportOptions
  {
    std::string crs;                     //!< the block CRS (projected or local engineering, metres); required
    std::filesystem::path imageFolder;   //!< where COLMAP's image names resolve; empty: looked for beside the model
    bool requireImageFiles = true;       //!< every image must exist, decode and have its camera's size
  };

  /**
   * Converts a model read from `modelFolder`. Throws std::invalid_argument
   * with one sentence when the CRS is not usable, nothing can be imported,
   * the model is inconsistent (a track naming a 2-D point that does not
   * exist) or, with requireImageFiles, an image file is missing or does not
   * match its camera. Nothing is written.
   */
  BlockImportSummary importColmapModel( const ColmapModel &model, const std::filesystem::path &modelFolder, const ColmapImportOptions &options );

  /**
   * The folder COLMAP's image names resolve in: the first of the model
   * folder, its parent's and grandparent's "images" folders, its parent and
   * grandparent that holds the first image. Empty when none does.
   */
  std::filesystem::path findColmapImageFolder( const ColmapModel &model, const std::filesystem::path &modelFolder );

} // namespace geostation

#endif // GEOSTATION_IO_COLMAPIMPORT_H

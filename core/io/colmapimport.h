/***************************************************************************
  colmapimport.h - a COLMAP sparse model as a GeoStation block
  -------------------------------------------------------------------------
  Cameras and poses are converted exactly (colmapconversion.h); every image
  becomes its own station (COLMAP has no exposure stations), in the order of
  the image names; the 3-D points become tie points with their observations.
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

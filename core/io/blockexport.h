/***************************************************************************
  blockexport.h - a block handed back: COLMAP text model, orientation CSV
  -------------------------------------------------------------------------
  The COLMAP model holds the block's oriented images with their cameras
  (colmapconversion.h) and, when given, tie points with their observations;
  image names are the block's image paths, relative to the block file's
  folder, so COLMAP (and GeoStation's importer) find the images there.
  Stations, times and a priori sigmas have no place in a COLMAP model.
 ***************************************************************************/
#ifndef GEOSTATION_IO_BLOCKEXPORT_H
#define GEOSTATION_IO_BLOCKEXPORT_H

#include <filesystem>
#include <string>
#include <vector>

#include "io/block.h"
#include "io/blockimport.h"
#include "io/colmapmodel.h"

namespace geostation
{

  struct BlockExportSummary
  {
    int cameras = 0;
    int images = 0;
    int tiePoints = 0;
    std::vector<std::string> dropped; //!< sentences: what could not be exported, and why
  };

  /**
   * The block as a COLMAP model. `tiePoints` and `observations` (may be
   * empty) become points3D and the images' 2-D points. Images that are not
   * oriented, have a scan affine (film) or a camera COLMAP cannot represent
   * are left out and named in the summary. Throws std::invalid_argument when
   * nothing is left.
   */
  ColmapModel colmapModelFromBlock( const Block &block, const std::vector<ImportedTiePoint> &tiePoints, const std::vector<ImportedObservation> &observations,
                                    BlockExportSummary *summary );

  /**
   * Writes the COLMAP text model into `folder` (created if needed): the
   * three files are written beside it first and moved in only when all are
   * complete. Throws like colmapModelFromBlock() and std::runtime_error.
   */
  BlockExportSummary exportBlockAsColmap( const Block &block, const std::filesystem::path &folder,
                                          const std::vector<ImportedTiePoint> &tiePoints = {}, const std::vector<ImportedObservation> &observations = {} );

  /**
   * Writes the exterior orientations as CSV, one row per image:
   * image_id,camera,station,path,X,Y,Z,omega,phi,kappa (metres, degrees,
   * docs/conventions.md §3) and sigma_X ... sigma_kappa (empty when unknown); an
   * image not yet oriented has empty values. Written through a temporary
   * file. Throws std::runtime_error.
   */
  BlockExportSummary exportBlockAsCsv( const Block &block, const std::filesystem::path &file );

} // namespace geostation

#endif // GEOSTATION_IO_BLOCKEXPORT_H

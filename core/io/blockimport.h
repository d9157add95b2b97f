/***************************************************************************
  blockimport.h - what every block importer returns, and georeferencing
  -------------------------------------------------------------------------
  An importer (COLMAP, ...) turns another package's orientations into a
  GeoStation block plus, where the source has them, tie points and their
  image observations (docs/conventions.md §6), and says in sentences what it
  converted and what it dropped and why. A model in an arbitrary frame is
  brought into the block CRS by a similarity transform fitted to known
  camera centres or control points (georeferenceImport()).
 ***************************************************************************/
#ifndef GEOSTATION_IO_BLOCKIMPORT_H
#define GEOSTATION_IO_BLOCKIMPORT_H

#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "geometry/similaritytransform.h"
#include "io/block.h"

namespace geostation
{

  struct ImportedTiePoint
  {
    std::string pointId;
    Eigen::Vector3d world = Eigen::Vector3d::Zero(); //!< block CRS once georeferenced
    double errorPx = -1.0;                           //!< the source's mean reprojection error, -1 unknown
  };

  struct ImportedObservation
  {
    std::string pointId;
    std::string imageId;
    Eigen::Vector2d pixelInImage = Eigen::Vector2d::Zero();
  };

  //! A control or check point brought along by an import (Metashape's markers), in the block CRS.
  struct ImportedControlPoint
  {
    std::string pointId;
    Eigen::Vector3d world = Eigen::Vector3d::Zero();
    std::optional<Eigen::Vector3d> sigmaM; //!< the source's accuracy (metres), if it gives one
    bool check = false;                    //!< a check point: its reference not used for the orientation
  };

  struct BlockImportSummary
  {
    std::string format;   //!< e.g. "colmap-binary"
    Block block;          //!< sourceFile set so that image paths resolve; save() rebases them
    std::vector<ImportedTiePoint> tiePoints;
    std::vector<ImportedObservation> observations;    //!< of tie points and of control points
    std::vector<ImportedControlPoint> controlPoints;
    std::map<std::string, std::string> imageIdBySourceName; //!< the source's image name (COLMAP's NAME) to the block's id
    std::vector<std::string> converted; //!< sentences: what was converted, and how
    std::vector<std::string> dropped;   //!< sentences: what was left out, and why
    std::vector<std::string> warnings;  //!< sentences: what was imported but deserves a look
    std::optional<SimilarityFitSummary> georeference;
    std::string georeferenceFrom;       //!< "camera centres" or "control points"
  };

  //! Known positions in the block CRS, by the source's image name (or block image id) or point id.
  struct KnownPositions
  {
    std::map<std::string, Eigen::Vector3d> cameraCentres;
    std::map<std::string, Eigen::Vector3d> controlPoints;
  };

  /**
   * Fits the similarity from the model's frame to the known positions (camera
   * centres if any are given, else control points: tie point ids) and applies
   * it to every exterior orientation and tie point. Names that match nothing
   * are reported in `dropped`. Throws std::invalid_argument (fewer than three
   * matches, collinear points) without changing the import.
   */
  void georeferenceImport( BlockImportSummary &import, const KnownPositions &known );

  //! The import's REPORT (docs/conventions.md §9) as JSON text: counts, sentences, the georeference with its residuals.
  std::string importReportJsonText( const BlockImportSummary &import );

  /**
   * Writes the observations as a CSV table point_id,image_id,col,row and
   * (when `pointsFile` is not empty) the tie points as point_id,X,Y,Z,error_px,
   * each through a temporary file renamed into place. Throws std::runtime_error.
   */
  void writeTiePointTables( const BlockImportSummary &import, const std::filesystem::path &observationsFile, const std::filesystem::path &pointsFile );

  /**
   * Writes the control and check points as the CSV table bundle_adjust's
   * GCPS reads: point_id,X,Y,Z,sx,sy,sz,role (sx, sy, sz empty where the
   * source gave no accuracy: fixed), through a temporary file renamed into
   * place. Throws std::runtime_error.
   */
  void writeControlTable( const BlockImportSummary &import, const std::filesystem::path &controlFile );

} // namespace geostation

#endif // GEOSTATION_IO_BLOCKIMPORT_H

/***************************************************************************
  scenesources.h - what a simulated scene reads from files: the DEM's block
  CRS and extent, a road line layer, an orthophoto
  -------------------------------------------------------------------------
  Each throws std::invalid_argument with one sentence when the file cannot
  be used (scenebuilder.h); what was reprojected or assumed is appended to
  `notes` for the report.
 ***************************************************************************/
#ifndef GEOSTATION_SIMULATION_SCENESOURCES_H
#define GEOSTATION_SIMULATION_SCENESOURCES_H

#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "simulation/roadnetwork.h"
#include "simulation/scene.h"

namespace geostation
{
  class Dem;

  //! Line features of an OGR layer ("file" or "file|layername=name") as roads in the block CRS.
  std::vector<Road> loadRoads( const std::string &path, const std::string &blockCrs, std::vector<std::string> &notes );

  //! A projected CRS for a DEM: its own, or the UTM zone of its centre when it is geographic.
  std::string blockCrsForDem( const Dem &dem, std::vector<std::string> &notes );

  //! Bounding box of the DEM's covered area in the block CRS (edges sampled; inset 3 % when reprojected).
  void demExtentInBlock( const Dem &dem, const std::string &blockCrs, Eigen::Vector2d &lo, Eigen::Vector2d &hi );

  //! The orthophoto warped to the block CRS over lo..hi (bilinear); it must cover 5 % of that.
  std::shared_ptr<OrthoTexture> loadOrtho( const std::string &path, const std::string &blockCrs, const Eigen::Vector2d &lo, const Eigen::Vector2d &hi );

  //! A number with 10 significant digits, for messages and GDAL arguments.
  std::string sceneNumber( double v );

} // namespace geostation

#endif // GEOSTATION_SIMULATION_SCENESOURCES_H

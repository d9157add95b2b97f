/***************************************************************************
  scenebuilder.h - the scene of a simulated survey, procedural or from data
  -------------------------------------------------------------------------
  Terrain comes from a GDAL DEM (any CRS, nodata filled) or is procedural
  (rolling hills around flat road corridors); roads come from a line layer
  (reprojected to the block CRS) or are procedural (straights, a curve and a
  junction); an orthophoto, if given, replaces the procedural ground texture.
  Objects (poles, signs, hydrants, trees, parked cars), manhole lids and
  signalised control targets are placed along the roads from the seed.
 ***************************************************************************/
#ifndef GEOSTATION_SIMULATION_SCENEBUILDER_H
#define GEOSTATION_SIMULATION_SCENEBUILDER_H

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "simulation/scene.h"

namespace geostation
{

  enum class SurveyPreset
  {
    Highway,      //!< a van rig driving along a road
    AerialStereo, //!< frame-camera strip with 60 % forward overlap
    ObliquePhoto, //!< one oblique photo over a hilly DEM
  };

  std::string surveyPresetName( SurveyPreset preset );
  //! Throws std::invalid_argument for an unknown name.
  SurveyPreset surveyPresetFromName( const std::string &name );

  struct SceneRequest
  {
    SurveyPreset preset = SurveyPreset::Highway;
    uint32_t seed = 1;
    std::string demPath;   //!< optional GDAL DEM
    std::string roadsPath; //!< optional OGR line layer
    std::string orthoPath; //!< optional orthophoto
    //! Extent needed around the site centre (local metres: x east, y north).
    Eigen::Vector2d extentMin = Eigen::Vector2d( -200, -200 ), extentMax = Eigen::Vector2d( 200, 200 );
    double nodeSpacingM = 0.5;
    double targetRadiusM = 0.25; //!< white disc radius of the control targets
    double textureFloorM = 0.0;  //!< see Scene::setTextureFloorM()
  };

  struct BuiltScene
  {
    std::string crs;                 //!< block CRS (EPSG code or WKT)
    Eigen::Vector2d siteCentre;      //!< block CRS
    std::unique_ptr<Scene> scene;
    std::vector<std::string> notes;  //!< what was reprojected or assumed, for the report
  };

  /**
   * Builds the scene. Throws std::invalid_argument with one sentence for bad
   * input: a DEM or road layer that cannot be read or has no CRS, roads or an
   * orthophoto that do not overlap the DEM.
   */
  BuiltScene buildScene( const SceneRequest &request );

} // namespace geostation

#endif // GEOSTATION_SIMULATION_SCENEBUILDER_H

/***************************************************************************
  surveyrig.h - the sensors of the simulator's presets and their poses
  -------------------------------------------------------------------------
  highway:       a van with 2-6 roof cameras (forward stereo pair about 2 m
                 apart, side and rear cameras) 2.5-2.7 m above the road,
                 driving in the right-hand lane of the first road;
  aerial_stereo: one frame camera along a strip with 60 % forward overlap;
  oblique_photo: one camera on high ground looking into the scene.
  The noisy block perturbs each station's vehicle (or camera) pose with the
  GNSS/INS sigmas, so the errors of one station's cameras are correlated as
  they are on a real rig.
 ***************************************************************************/
#ifndef GEOSTATION_SIMULATION_SURVEYRIG_H
#define GEOSTATION_SIMULATION_SURVEYRIG_H

#include <cstdint>

#include <Eigen/Core>

#include "io/block.h"
#include "simulation/scenebuilder.h"

namespace geostation
{

  struct SimulationOptions;

  //! Preset defaults resolved from the options.
  struct RigSettings
  {
    int stations = 1;
    int width = 640, height = 480;
    Eigen::Vector2d extentMin, extentMax; //!< scene extent around the site centre
    double nodeSpacingM = 0.5;
    double targetRadiusM = 0.25;
    double textureFloorM = 0.0; //!< aerial: just above the ground pixel size (see Scene::setTextureFloorM())
    ExteriorSigma sigma; //!< GNSS/INS quality of the noisy block
  };

  RigSettings rigSettings( const SimulationOptions &options );

  //! The scene a simulation needs: its preset, seed, inputs and the rig's extent and sizes.
  SceneRequest sceneRequest( const SimulationOptions &options, const RigSettings &settings );

  /**
   * The exact block (cameras, stations, images with true exterior
   * orientation) and, in `noisy`, the same with GNSS/INS errors and sigmas.
   * Throws std::invalid_argument when the run does not fit the roads.
   */
  void buildRig( const SimulationOptions &options, const RigSettings &settings, const BuiltScene &scene, Block &truth, Block &noisy );

} // namespace geostation

#endif // GEOSTATION_SIMULATION_SURVEYRIG_H

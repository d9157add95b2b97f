/***************************************************************************
  surveysimulator.h - photo-realistic synthetic surveys with exact truth
  -------------------------------------------------------------------------
  simulateSurvey() builds a scene (procedural or from a DEM, a road layer
  and an orthophoto), flies or drives a sensor through it, renders every
  image by ray casting through the camera model and writes, into OUTPUT_DIR:

    block.geostation.json   orientation with realistic GNSS/INS errors
    truth.geostation.json   the exact orientation
    images/<id>.tif         8-bit RGB GeoTIFFs in pixel space
    terrain.tif             the terrain surface (Float32, block CRS)
    truth.gpkg              objects, roads, control, occluders layers and
                            the image_truth table (point_id, image_id, col, row;
                            control targets: disc_px, disc_in_view, disc_in_sun)
    simulation.json         what was simulated: options, counts, notes

  Everything is written to a staging folder first and moved into place at
  the end, so a failed or cancelled run leaves OUTPUT_DIR as it was.
  A fixed seed gives identical output.
 ***************************************************************************/
#ifndef GEOSTATION_SIMULATION_SURVEYSIMULATOR_H
#define GEOSTATION_SIMULATION_SURVEYSIMULATOR_H

#include <cstdint>
#include <filesystem>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "progress/progress.h"
#include "simulation/degradation.h"
#include "io/block.h"
#include "simulation/scenebuilder.h"

namespace geostation
{

  //! Thrown when the progress callback asks to stop.
  class SimulationCancelled : public std::runtime_error
  {
    public:
      SimulationCancelled() : std::runtime_error( "the simulation was cancelled" ) {}
  };

  struct SimulationOptions
  {
    SurveyPreset preset = SurveyPreset::Highway;
    uint32_t seed = 1;
    std::filesystem::path outputDir;
    std::string demPath;    //!< optional GDAL DEM (any CRS, nodata allowed)
    std::string roadsPath;  //!< optional OGR line layer (reprojected)
    std::string orthoPath;  //!< optional orthophoto GeoTIFF draped as ground texture
    int stations = 0;       //!< 0: the preset's default (highway 30, aerial_stereo 3, oblique_photo 1)
    int imageWidth = 0;     //!< 0: the preset's default (640, 1024, 1024)
    int imageHeight = 0;    //!< 0: the preset's default (480, 1024, 768)
    int cameras = 3;        //!< highway: cameras on the van, 2..6
    bool oneCameraModel = false;    //!< highway: the van's cameras identical, one camera entry ("van") for all (a rig of one model)
    double stationSpacingM = 5.0;   //!< highway: metres between stations
    double groundPixelSizeM = 0.10; //!< aerial_stereo: ground sample distance
    bool scannedFilm = false;       //!< oblique_photo: a scanned film photo with fiducial marks (see filmscan.h)
    DegradationOptions degradation;
    double poseNoiseScale = 1.0;    //!< multiplies the preset's GNSS/INS sigmas (0: block = truth)
    int supersampling = 3;          //!< n x n samples in edge pixels (4n x 4n on target edges)
    int threads = 0;                //!< 0: all cores
    //! Told the fraction done and the stage, and asked whether to stop: a stop throws SimulationCancelled.
    Progress progress;

    //! Throws std::invalid_argument naming the first bad value.
    void validate() const;
  };

  struct SimulationSummary
  {
    std::string crs;
    int images = 0;
    int stations = 0;
    long pixels = 0;
    long rays = 0;
    double renderSeconds = 0.0;
    int objects = 0;
    int controlPoints = 0;
    int roadLines = 0;
    long imageTruthRows = 0;
    std::filesystem::path blockFile, truthBlockFile, truthGeoPackage, terrainFile;
    std::vector<std::string> notes;
  };

  /**
   * Throws std::invalid_argument when none of a 24 x 18 grid of the image's
   * rays meets the terrain or an object (a camera looking at the sky only).
   */
  void requireGroundInView( const Scene &scene, const Block &block, const BlockImage &image );

  /**
   * Runs a simulation. Throws std::invalid_argument (bad options or input,
   * one sentence), SimulationCancelled, or std::runtime_error (I/O).
   */
  SimulationSummary simulateSurvey( const SimulationOptions &options );

} // namespace geostation

#endif // GEOSTATION_SIMULATION_SURVEYSIMULATOR_H

/***************************************************************************
  surveysimulator.cpp - runs a simulated survey and writes its outputs
 ***************************************************************************/
#include "simulation/surveysimulator.h"

#include <chrono>
#include <fstream>
#include <thread>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include "io/rasterfile.h"
#include "simulation/filmscan.h"
#include "simulation/renderer.h"
#include "simulation/surveyrig.h"
#include "simulation/truthwriter.h"

namespace geostation
{
  namespace
  {
    nlohmann::json degradationJson( const DegradationOptions &d )
    {
      return { { "exposure", d.exposure }, { "vignetting", d.vignetting }, { "blur_sigma_px", d.blurSigmaPx }, { "noise_sigma", d.noiseSigma },
               { "bit_error_rate", d.bitErrorRate }, { "jpeg_quality", d.jpegQuality } };
    }
  }

  void requireGroundInView( const Scene &scene, const Block &block, const BlockImage &image )
  {
    const Camera &camera = block.cameraOf( image );
    const OrientedImage oriented = block.orientedImage( image );
    for ( int j = 0; j < 18; ++j )
      for ( int i = 0; i < 24; ++i )
        if ( const std::optional<Ray> ray = oriented.worldRayFromPixel( Eigen::Vector2d( ( i + 0.5 ) * camera.width / 24.0, ( j + 0.5 ) * camera.height / 18.0 ) ) )
          if ( !scene.trace( ray->origin, ray->direction, 1.0 / camera.f ).sky )
            return;
    throw std::invalid_argument( "image " + image.id + " looks at the sky only: no ray of it meets the terrain (check the DEM's extent and the camera's orientation)" );
  }

  void SimulationOptions::validate() const
  {
    if ( outputDir.empty() )
      throw std::invalid_argument( "no output folder given" );
    if ( stations < 0 || stations > 2000 )
      throw std::invalid_argument( "the number of stations must be between 1 and 2000" );
    if ( ( imageWidth != 0 && ( imageWidth < 32 || imageWidth > 8000 ) ) || ( imageHeight != 0 && ( imageHeight < 32 || imageHeight > 8000 ) ) )
      throw std::invalid_argument( "image width and height must be between 32 and 8000 pixels" );
    if ( preset == SurveyPreset::Highway && ( cameras < 2 || cameras > 6 ) )
      throw std::invalid_argument( "the highway van carries 2 to 6 cameras" );
    if ( !( stationSpacingM >= 1.0 && stationSpacingM <= 100.0 ) )
      throw std::invalid_argument( "the station spacing must be between 1 and 100 m" );
    if ( !( groundPixelSizeM >= 0.01 && groundPixelSizeM <= 5.0 ) )
      throw std::invalid_argument( "the ground pixel size must be between 0.01 and 5 m" );
    if ( !( poseNoiseScale >= 0.0 && poseNoiseScale <= 100.0 ) )
      throw std::invalid_argument( "the pose noise scale must be between 0 and 100" );
    if ( scannedFilm && preset != SurveyPreset::ObliquePhoto )
      throw std::invalid_argument( "the scanned-film variant belongs to the oblique_photo preset" );
    if ( supersampling < 1 || supersampling > 16 )
      throw std::invalid_argument( "supersampling must be between 1 and 16" );
    degradation.validate();
  }

  SimulationSummary simulateSurvey( const SimulationOptions &options )
  {
    options.validate();
    const auto report = [&]( double fraction, const std::string &message )
    {
      if ( !options.progress.report( fraction, message ) )
        throw SimulationCancelled();
    };
    SimulationSummary summary;
    const RigSettings settings = rigSettings( options );

    report( 0.0, "building the scene" );
    const BuiltScene built = buildScene( sceneRequest( options, settings ) );
    const Scene &scene = *built.scene;
    summary.crs = built.crs;
    summary.notes = built.notes;

    Block truth, noisy;
    buildRig( options, settings, built, truth, noisy );
    for ( const BlockImage &image : truth.images )
      requireGroundInView( scene, truth, image );

    // Stage everything next to the output, move into place at the end.
    std::filesystem::create_directories( options.outputDir );
    const std::filesystem::path staging = options.outputDir / ( ".simulate-staging-" + std::to_string( ::getpid() ) );
    std::filesystem::remove_all( staging );
    std::filesystem::create_directories( staging / "images" );
    try
    {
      const int threads = options.threads > 0 ? options.threads : std::max( 1u, std::thread::hardware_concurrency() );
      RenderOptions renderOptions;
      renderOptions.supersampling = options.supersampling;
      renderOptions.threads = threads;
      RenderSummary renderSummary;
      std::map<std::string, std::unique_ptr<CameraRays>> rays;
      for ( const Camera &camera : truth.cameras )
        rays[camera.id] = std::make_unique<CameraRays>( camera );
      const auto start = std::chrono::steady_clock::now();
      for ( size_t i = 0; i < truth.images.size(); ++i )
      {
        const BlockImage &image = truth.images[i];
        report( 0.02 + 0.83 * i / truth.images.size(), "rendering " + image.id );
        const OrientedImage oriented = truth.orientedImage( image );
        cv::Mat linear = renderImage( scene, oriented, rays[image.cameraId].get(), renderOptions, &renderSummary );
        if ( image.innerOrientation )
          drawFiducialMarks( linear, truth.cameraOf( image ), oriented );
        const cv::Mat rgb = degradeAndQuantise( linear, options.degradation, options.seed * 2654435761u + static_cast<uint32_t>( i ) );
        writeGeoTiffLike( ( staging / image.path ).string(), rgb, RasterImage() ); // pixel space: no georeferencing
      }
      summary.renderSeconds = std::chrono::duration<double>( std::chrono::steady_clock::now() - start ).count();
      summary.pixels = renderSummary.pixels;
      summary.rays = renderSummary.rays;

      report( 0.86, "computing the image truth" );
      const std::vector<TruthLine> lines = roadTruthLines( scene );
      const std::vector<TruthPoint> points = truthPoints( scene, lines );
      const std::vector<ImageTruthRow> rows = imageTruth( scene, truth, points, [&]( size_t done )
      { report( 0.86 + 0.08 * done / truth.images.size(), "computing the image truth" ); } );
      report( 0.95, "writing the truth" );
      writeTruthGeoPackage( staging / "truth.gpkg", built.crs, scene, lines, rows );
      scene.terrain().writeGeoTiff( ( staging / "terrain.tif" ).string(), built.crs );
      truth.save( staging / "truth.geostation.json" );
      noisy.save( staging / "block.geostation.json" );

      for ( const SceneObject &object : scene.objects() )
        summary.objects += ( object.kind == ObjectKind::Tree || object.kind == ObjectKind::Car ) ? 0 : 1;
      for ( const GroundMark &mark : scene.marks() )
        ( mark.kind == GroundMarkKind::Target ? summary.controlPoints : summary.objects ) += 1;
      summary.roadLines = static_cast<int>( lines.size() );
      summary.imageTruthRows = static_cast<long>( rows.size() );
      summary.images = static_cast<int>( truth.images.size() );
      summary.stations = static_cast<int>( truth.stations.size() );

      nlohmann::json record = {
        { "preset", surveyPresetName( options.preset ) }, { "seed", options.seed }, { "crs", built.crs },
        { "stations", summary.stations }, { "images", summary.images },
        { "image_width", settings.width }, { "image_height", settings.height },
        { "dem", options.demPath }, { "roads", options.roadsPath }, { "ortho", options.orthoPath },
        { "station_spacing_m", options.stationSpacingM }, { "scanned_film", options.scannedFilm }, { "ground_pixel_size_m", options.groundPixelSizeM },
        { "pose_sigma", { { "X", settings.sigma.x }, { "Y", settings.sigma.y }, { "Z", settings.sigma.z }, { "omega", settings.sigma.omegaDeg },
            { "phi", settings.sigma.phiDeg }, { "kappa", settings.sigma.kappaDeg } } },
        { "degradation", degradationJson( options.degradation ) }, { "supersampling", options.supersampling },
        { "objects", summary.objects }, { "control_points", summary.controlPoints }, { "road_lines", summary.roadLines },
        { "image_truth_rows", summary.imageTruthRows }, { "render_seconds", summary.renderSeconds },
        { "rays", summary.rays }, { "pixels", summary.pixels }, { "notes", summary.notes } };
      std::ofstream( staging / "simulation.json" ) << record.dump( 2 ) << "\n";

      report( 0.99, "moving the outputs into place" );
      for ( const char *name : { "images", "truth.gpkg", "terrain.tif", "truth.geostation.json", "block.geostation.json", "simulation.json" } )
      {
        std::filesystem::remove_all( options.outputDir / name );
        std::filesystem::rename( staging / name, options.outputDir / name );
      }
      std::filesystem::remove_all( staging );
    }
    catch ( ... )
    {
      std::error_code ignored;
      std::filesystem::remove_all( staging, ignored );
      throw;
    }
    summary.blockFile = options.outputDir / "block.geostation.json";
    summary.truthBlockFile = options.outputDir / "truth.geostation.json";
    summary.truthGeoPackage = options.outputDir / "truth.gpkg";
    summary.terrainFile = options.outputDir / "terrain.tif";
    report( 1.0, "done" );
    return summary;
  }

} // namespace geostation

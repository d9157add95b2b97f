/***************************************************************************
  surveyrig.cpp - cameras, stations and poses of the simulator's presets
 ***************************************************************************/
#include "simulation/surveyrig.h"

#include <cmath>
#include <cstdio>
#include <random>
#include <stdexcept>

#include <Eigen/Geometry>

#include "geometry/rotation.h"
#include "simulation/filmscan.h"
#include "simulation/surveysimulator.h"

namespace geostation
{
  namespace
  {
    Eigen::Matrix3d rotX( double a )
    {
      Eigen::Matrix3d r;
      r << 1, 0, 0, 0, std::cos( a ), -std::sin( a ), 0, std::sin( a ), std::cos( a );
      return r;
    }
    Eigen::Matrix3d rotY( double a )
    {
      Eigen::Matrix3d r;
      r << std::cos( a ), 0, std::sin( a ), 0, 1, 0, -std::sin( a ), 0, std::cos( a );
      return r;
    }
    Eigen::Matrix3d rotZ( double a )
    {
      Eigen::Matrix3d r;
      r << std::cos( a ), -std::sin( a ), 0, std::sin( a ), std::cos( a ), 0, 0, 0, 1;
      return r;
    }

    //! Camera axes (x right, y up, z backwards) for a viewing direction, with no roll.
    Eigen::Matrix3d cameraAxesLookingAlong( const Eigen::Vector3d &view )
    {
      const Eigen::Vector3d v = view.normalized();
      Eigen::Vector3d right = v.cross( Eigen::Vector3d::UnitZ() );
      if ( right.norm() < 1e-9 )
        right = Eigen::Vector3d::UnitX(); // nadir: image right = east
      right.normalize();
      const Eigen::Vector3d z = -v;
      const Eigen::Vector3d y = z.cross( right );
      Eigen::Matrix3d axes;
      axes.col( 0 ) = right;
      axes.col( 1 ) = y;
      axes.col( 2 ) = z;
      return axes;
    }

    std::string isoTime( double secondsAfterStart )
    {
      // 2026-05-04T10:00:00.000Z + seconds (runs shorter than a day)
      const long ms = std::lround( secondsAfterStart * 1000.0 );
      const long total = 10 * 3600 * 1000L + ms;
      char buffer[40];
      std::snprintf( buffer, sizeof buffer, "2026-05-04T%02ld:%02ld:%02ld.%03ldZ", total / 3600000, ( total / 60000 ) % 60, ( total / 1000 ) % 60, total % 1000 );
      return buffer;
    }

    std::string stationId( int i )
    {
      char buffer[16];
      std::snprintf( buffer, sizeof buffer, "S%04d", i + 1 );
      return buffer;
    }

    struct Mount
    {
      const char *id;
      const char *suffix;
      Eigen::Vector3d position; //!< vehicle frame: x forward, y left, z up (m)
      double yawDeg, downDeg;
    };
    const Mount kVanMounts[] = {
      { "front_left", "FL", { 0.6, 1.0, 2.65 }, 0.0, 7.0 },
      { "front_right", "FR", { 0.6, -1.0, 2.65 }, 0.0, 7.0 },
      { "side_right", "SR", { 0.2, -0.9, 2.55 }, -75.0, 12.0 },
      { "side_left", "SL", { 0.2, 0.9, 2.55 }, 75.0, 12.0 },
      { "rear_left", "RL", { -1.6, 0.8, 2.5 }, 180.0, 8.0 },
      { "rear_right", "RR", { -1.6, -0.8, 2.5 }, 180.0, 8.0 },
    };
  }

  RigSettings rigSettings( const SimulationOptions &options )
  {
    RigSettings s;
    switch ( options.preset )
    {
      case SurveyPreset::Highway:
      {
        s.stations = options.stations > 0 ? options.stations : 30;
        s.width = options.imageWidth > 0 ? options.imageWidth : 640;
        s.height = options.imageHeight > 0 ? options.imageHeight : 480;
        const double run = 20.0 + s.stations * options.stationSpacingM;
        s.extentMin = Eigen::Vector2d( -120, -180 );
        s.extentMax = Eigen::Vector2d( run + 260, std::max( 220.0, 0.5 * run + 120 ) );
        s.nodeSpacingM = 0.5;
        s.targetRadiusM = 0.25;
        s.sigma = { 0.10, 0.10, 0.15, 0.02, 0.02, 0.05 };
        break;
      }
      case SurveyPreset::AerialStereo:
      {
        s.stations = options.stations > 0 ? options.stations : 3;
        s.width = options.imageWidth > 0 ? options.imageWidth : 1024;
        s.height = options.imageHeight > 0 ? options.imageHeight : 1024;
        const double gsd = options.groundPixelSizeM;
        const double base = 0.4 * s.width * gsd;
        const double halfX = 0.5 * ( s.stations - 1 ) * base + 0.75 * s.width * gsd + 30;
        const double halfY = 0.75 * s.height * gsd + 30;
        s.extentMin = Eigen::Vector2d( -halfX, -halfY );
        s.extentMax = Eigen::Vector2d( halfX, halfY );
        s.nodeSpacingM = std::max( 0.5, 4.0 * gsd );
        s.targetRadiusM = std::max( 0.25, 4.0 * gsd );
        s.textureFloorM = 1.5 * gsd;
        s.sigma = { 0.05, 0.05, 0.08, 0.005, 0.005, 0.008 };
        break;
      }
      case SurveyPreset::ObliquePhoto:
      {
        s.stations = 1;
        s.width = options.imageWidth > 0 ? options.imageWidth : 1024;
        s.height = options.imageHeight > 0 ? options.imageHeight : 768;
        s.extentMin = Eigen::Vector2d( -320, -320 );
        s.extentMax = Eigen::Vector2d( 420, 420 );
        s.nodeSpacingM = 1.0;
        s.targetRadiusM = 1.5;
        s.sigma = { 2.0, 2.0, 2.0, 0.5, 0.5, 0.5 };
        break;
      }
    }
    const double k = options.poseNoiseScale;
    s.sigma = { s.sigma.x * k, s.sigma.y * k, s.sigma.z * k, s.sigma.omegaDeg * k, s.sigma.phiDeg * k, s.sigma.kappaDeg * k };
    return s;
  }

  SceneRequest sceneRequest( const SimulationOptions &options, const RigSettings &settings )
  {
    SceneRequest request;
    request.preset = options.preset;
    request.seed = options.seed;
    request.demPath = options.demPath;
    request.roadsPath = options.roadsPath;
    request.orthoPath = options.orthoPath;
    request.extentMin = settings.extentMin;
    request.extentMax = settings.extentMax;
    request.nodeSpacingM = settings.nodeSpacingM;
    request.targetRadiusM = settings.targetRadiusM;
    request.textureFloorM = settings.textureFloorM;
    return request;
  }

  namespace
  {
    //! A station's pose: world from vehicle (x forward, y left, z up) and the vehicle's origin (block CRS).
    struct RigPose
    {
      Eigen::Matrix3d worldFromVehicle;
      Eigen::Vector3d origin;
    };

    //! The cameras with their mounts (vehicle from camera [R | t]) and every station's exact pose.
    struct RigLayout
    {
      std::vector<std::pair<Camera, Eigen::Matrix<double, 3, 4>>> cameras;
      std::vector<RigPose> exact;
    };

    //! The van in the first road's right-hand outer lane, its stations every stationSpacingM from 20 m, pitched and rolled with the road; options.cameras of kVanMounts.
    RigLayout vanLayout( const SimulationOptions &options, const RigSettings &settings, const Scene &scene, std::mt19937 &random, std::normal_distribution<double> &gauss )
    {
      RigLayout layout;
      const double w = settings.width, h = settings.height;
      const RoadNetwork &roads = scene.roads();
      const Road &road = roads.roads().front();
      const double laneOffset = -( road.lanesPerDirection - 0.5 ) * road.laneWidthM;
      const double start = 20.0;
      if ( start + ( settings.stations - 1 ) * options.stationSpacingM > roads.length( 0 ) - 5.0 )
        throw std::invalid_argument( "the run of " + std::to_string( settings.stations ) + " stations every " + std::to_string( options.stationSpacingM ) +
                                     " m is longer than the road " + road.id + " (" + std::to_string( static_cast<int>( roads.length( 0 ) ) ) + " m)" );
      for ( int i = 0; i < settings.stations; ++i )
      {
        Eigen::Vector2d tangent;
        const double s = start + i * options.stationSpacingM;
        const Eigen::Vector2d p = roads.pointAt( 0, s, laneOffset, &tangent );
        const Eigen::Vector2d left( -tangent.y(), tangent.x() );
        const auto groundAt = [&]( const Eigen::Vector2d &q )
        {
          const std::optional<double> z = scene.terrain().heightAt( q.x(), q.y() );
          if ( !z )
            throw std::invalid_argument( "station " + stationId( i ) + " lies outside the terrain" );
          return *z;
        };
        const double pitch = std::atan2( groundAt( p + 2.0 * tangent ) - groundAt( p - 2.0 * tangent ), 4.0 );
        const double roll = std::atan2( groundAt( p + 0.9 * left ) - groundAt( p - 0.9 * left ), 1.8 );
        const double bounce = degToRad( 0.15 ); // suspension
        RigPose pose;
        pose.origin = Eigen::Vector3d( p.x(), p.y(), groundAt( p ) );
        pose.worldFromVehicle = rotZ( std::atan2( tangent.y(), tangent.x() ) ) * rotY( -pitch + bounce * gauss( random ) ) * rotX( roll + bounce * gauss( random ) );
        layout.exact.push_back( pose );
      }
      const int n = options.cameras;
      for ( int k = 0; k < n; ++k )
      {
        const Mount &mount = kVanMounts[k];
        const int model = options.oneCameraModel ? 0 : k; // the intrinsics differ a little from camera to camera
        Camera camera;
        camera.id = options.oneCameraModel ? "van" : mount.id;
        camera.width = settings.width;
        camera.height = settings.height;
        camera.f = 0.8 * w * ( 1.0 + 0.01 * model );
        camera.aspect = 1.0;
        camera.cx = 0.5 * w + 1.3 - 0.4 * model;
        camera.cy = 0.5 * h - 0.8 + 0.3 * model;
        camera.pixelSizeMm = 0.0074 * 640.0 / w;
        camera.distortion.model = DistortionModel::OpenCV;
        camera.distortion.coeffs = { -0.12 + 0.01 * model, 0.03, 2e-4, -1e-4, 0.0 };
        const double yaw = degToRad( mount.yawDeg ), down = degToRad( mount.downDeg );
        const Eigen::Vector3d view( std::cos( down ) * std::cos( yaw ), std::cos( down ) * std::sin( yaw ), -std::sin( down ) );
        Eigen::Matrix<double, 3, 4> vehicleFromCamera;
        vehicleFromCamera.leftCols<3>() = cameraAxesLookingAlong( view );
        vehicleFromCamera.col( 3 ) = mount.position;
        layout.cameras.push_back( { camera, vehicleFromCamera } );
      }
      return layout;
    }

    //! A frame camera along a strip over the site centre, 60 % forward overlap at the ground pixel size asked for.
    RigLayout aerialLayout( const SimulationOptions &options, const RigSettings &settings, const BuiltScene &built, std::mt19937 &random,
                            std::normal_distribution<double> &gauss )
    {
      RigLayout layout;
      const Scene &scene = *built.scene;
      const double w = settings.width, h = settings.height;
      const double gsd = options.groundPixelSizeM;
      Camera camera;
      camera.id = "frame";
      camera.width = settings.width;
      camera.height = settings.height;
      camera.f = 0.9 * w;
      camera.cx = 0.5 * w + 0.7;
      camera.cy = 0.5 * h - 1.1;
      camera.pixelSizeMm = 0.012;
      camera.distortion.model = DistortionModel::BrownPhoto;
      camera.distortion.coeffs = { -2.0e-5, 1.5e-8, 1.0e-6, -8.0e-7, 0.0 };
      Eigen::Matrix<double, 3, 4> identity = Eigen::Matrix<double, 3, 4>::Zero();
      identity.leftCols<3>().setIdentity();
      layout.cameras.push_back( { camera, identity } );
      const std::optional<double> centreHeight = scene.terrain().heightAt( built.siteCentre.x(), built.siteCentre.y() );
      const double flyingHeight = ( centreHeight ? *centreHeight : scene.terrain().maxHeight() ) + camera.f * gsd;
      const double base = 0.4 * w * gsd;
      for ( int i = 0; i < settings.stations; ++i )
      {
        RigPose pose;
        pose.origin = Eigen::Vector3d( built.siteCentre.x() + ( i - 0.5 * ( settings.stations - 1 ) ) * base, built.siteCentre.y() + 2.0 * gauss( random ), flyingHeight + 1.5 * gauss( random ) );
        pose.worldFromVehicle = rotX( degToRad( 0.8 * gauss( random ) ) ) * rotY( degToRad( 0.8 * gauss( random ) ) ) * rotZ( degToRad( 1.0 * gauss( random ) ) );
        layout.exact.push_back( pose );
      }
      return layout;
    }

    //! One oblique camera 140 m above the terrain south-west of the site, looking at a point north-east of its centre; digital or scanned film.
    RigLayout obliqueLayout( const SimulationOptions &options, const RigSettings &settings, const BuiltScene &built, std::mt19937 &random,
                             std::normal_distribution<double> &gauss )
    {
      RigLayout layout;
      const Scene &scene = *built.scene;
      const double w = settings.width, h = settings.height;
      Camera camera;
      camera.id = options.scannedFilm ? "film" : "oblique";
      camera.width = settings.width;
      camera.height = settings.height;
      camera.f = 1.1 * w;
      camera.cx = 0.5 * w - 2.1;
      camera.cy = 0.5 * h + 1.6;
      camera.distortion.model = DistortionModel::BrownPhoto;
      if ( options.scannedFilm )
      {
        // a 100 x 75 mm film frame scanned at 0.1 mm (for the default 1024 x 768)
        camera.pixelSizeMm = 0.1 * 1024.0 / w;
        const double s = *camera.pixelSizeMm / 0.0065; // the digital lens scaled to the film format
        camera.distortion.coeffs = { -1.0e-3 / ( s * s ), 2.0e-6 / ( s * s * s * s ), 3.0e-5 / s, -2.0e-5 / s, 0.0 };
        camera.fiducials = filmFiducials( camera );
      }
      else
      {
        camera.pixelSizeMm = 0.0065 * 1024.0 / w;
        camera.distortion.coeffs = { -1.0e-3, 2.0e-6, 3.0e-5, -2.0e-5, 0.0 };
      }
      Eigen::Matrix<double, 3, 4> identity = Eigen::Matrix<double, 3, 4>::Zero();
      identity.leftCols<3>().setIdentity();
      layout.cameras.push_back( { camera, identity } );
      const Eigen::Vector2d target = built.siteCentre + Eigen::Vector2d( 40, 40 );
      const Eigen::Vector2d position = built.siteCentre + Eigen::Vector2d( -250, -250 );
      const std::optional<double> targetZ = scene.terrain().heightAt( target.x(), target.y() );
      const std::optional<double> groundZ = scene.terrain().heightAt( position.x(), position.y() );
      if ( !targetZ || !groundZ )
        throw std::invalid_argument( "the terrain does not reach the oblique camera's position and target" );
      RigPose pose;
      pose.origin = Eigen::Vector3d( position.x(), position.y(), std::max( *groundZ, *targetZ ) + 140.0 );
      pose.worldFromVehicle = cameraAxesLookingAlong( Eigen::Vector3d( target.x(), target.y(), *targetZ ) - pose.origin ) * rotZ( degToRad( 1.5 * gauss( random ) ) );
      // the camera has the identity mount: the pose is the camera's own
      layout.exact.push_back( pose );
      return layout;
    }

    //! The pose with the GNSS/INS errors of `sigma`.
    RigPose perturbed( const RigPose &pose, const ExteriorSigma &sigma, std::mt19937 &random, std::normal_distribution<double> &gauss )
    {
      RigPose p = pose;
      p.origin += Eigen::Vector3d( sigma.x * gauss( random ), sigma.y * gauss( random ), sigma.z * gauss( random ) );
      p.worldFromVehicle = rotZ( degToRad( sigma.kappaDeg * gauss( random ) ) ) * p.worldFromVehicle *
                           rotX( degToRad( sigma.omegaDeg * gauss( random ) ) ) * rotY( degToRad( sigma.phiDeg * gauss( random ) ) );
      return p;
    }
  } // namespace

  void buildRig( const SimulationOptions &options, const RigSettings &settings, const BuiltScene &built, Block &truth, Block &noisy )
  {
    truth = Block();
    truth.crs = built.crs;
    std::mt19937 random( options.seed * 104729u + 5u );
    std::normal_distribution<double> gauss( 0.0, 1.0 );
    const ExteriorSigma &sigma = settings.sigma;
    RigLayout layout;
    switch ( options.preset )
    {
      case SurveyPreset::Highway:
        layout = vanLayout( options, settings, *built.scene, random, gauss );
        break;
      case SurveyPreset::AerialStereo:
        layout = aerialLayout( options, settings, built, random, gauss );
        break;
      case SurveyPreset::ObliquePhoto:
        layout = obliqueLayout( options, settings, built, random, gauss );
        break;
    }
    const std::vector<std::pair<Camera, Eigen::Matrix<double, 3, 4>>> &cameras = layout.cameras;
    const std::vector<RigPose> &exact = layout.exact;

    for ( const auto &entry : cameras )
      if ( !truth.findCamera( entry.first.id ) )
        truth.cameras.push_back( entry.first );
    const double secondsPerStation = options.preset == SurveyPreset::Highway ? options.stationSpacingM / 12.0 : 2.0;
    for ( size_t i = 0; i < exact.size(); ++i )
    {
      Station station;
      station.id = stationId( static_cast<int>( i ) );
      station.time = isoTime( i * secondsPerStation );
      station.trajectory = options.preset == SurveyPreset::AerialStereo ? "strip 1" : "P-line 1";
      truth.stations.push_back( station );
      for ( const auto &entry : cameras )
      {
        const Camera &camera = entry.first;
        BlockImage image;
        image.cameraId = camera.id;
        image.stationId = station.id;
        truth.images.push_back( image );
      }
    }
    // image ids, paths and exact orientation
    size_t index = 0;
    for ( size_t i = 0; i < exact.size(); ++i )
      for ( size_t k = 0; k < cameras.size(); ++k, ++index )
      {
        BlockImage &image = truth.images[index];
        image.id = options.preset == SurveyPreset::Highway ? truth.stations[i].id + "_" + kVanMounts[k].suffix : truth.stations[i].id;
        image.path = "images/" + image.id + ".tif";
        const Eigen::Matrix3d R = exact[i].worldFromVehicle * cameras[k].second.leftCols<3>();
        image.exterior = ExteriorOrientation::fromCentreAndRotation( exact[i].origin + exact[i].worldFromVehicle * cameras[k].second.col( 3 ), R );
      }
    if ( options.scannedFilm && options.preset == SurveyPreset::ObliquePhoto )
      for ( BlockImage &image : truth.images )
        image.innerOrientation = ImageInnerOrientation { simulatedScan( truth.camera( image.cameraId ), random ), 0.0 };
    noisy = truth;
    for ( BlockImage &image : noisy.images )
      image.innerOrientation.reset(); // to be measured from the fiducial marks
    index = 0;
    for ( size_t i = 0; i < exact.size(); ++i )
    {
      const RigPose pose = perturbed( exact[i], sigma, random, gauss );
      for ( size_t k = 0; k < cameras.size(); ++k, ++index )
      {
        BlockImage &image = noisy.images[index];
        image.exterior = ExteriorOrientation::fromCentreAndRotation( pose.origin + pose.worldFromVehicle * cameras[k].second.col( 3 ), pose.worldFromVehicle * cameras[k].second.leftCols<3>() );
        if ( options.poseNoiseScale > 0.0 )
          image.exterior->sigma = sigma;
      }
    }
  }

} // namespace geostation

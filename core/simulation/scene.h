/***************************************************************************
  scene.h - the simulated world: terrain, roads, objects, marks and light
  -------------------------------------------------------------------------
  trace() follows one viewing ray to the first surface (terrain or object)
  and returns its shaded colour: Lambert shading under a sun with object
  shadows on the ground, procedural ground textures band-limited to the
  pixel footprint, road markings with worn paint, manhole lids and the
  signalised control targets. isVisible() answers whether a truth point is
  seen from a projection centre.
 ***************************************************************************/
#ifndef GEOSTATION_SIMULATION_SCENE_H
#define GEOSTATION_SIMULATION_SCENE_H

#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "simulation/heightfield.h"
#include "simulation/roadnetwork.h"
#include "simulation/sceneobjects.h"
#include "simulation/spatialgrid.h"

namespace geostation
{

  //! An orthophoto draped over the terrain instead of the procedural ground texture.
  struct OrthoTexture
  {
    cv::Mat rgb;           //!< CV_8UC3, R G B, north up
    double originX = 0.0;  //!< x of the top-left corner of the top-left pixel (block CRS)
    double originY = 0.0;  //!< y of that corner
    double pixelSizeM = 1.0;
  };

  struct SceneLighting
  {
    double sunAzimuthDeg = 135.0;   //!< clockwise from north
    double sunElevationDeg = 38.0;
    double ambient = 0.42;          //!< fraction of light that reaches shadows
  };

  //! One traced ray.
  struct SurfaceSample
  {
    Eigen::Vector3f rgb = Eigen::Vector3f::Zero(); //!< linear 0..1
    uint32_t key = 0;   //!< what was hit (material, object, part, shadow); differs across edges
    bool ground = false;
    bool sky = true;
    double t = 0.0;
  };

  class Scene
  {
    public:
      Scene( HeightField terrain, RoadNetwork roads, std::vector<SceneObject> objects, std::vector<GroundMark> marks,
             const SceneLighting &lighting, uint32_t seed );

      const HeightField &terrain() const { return mTerrain; }
      const RoadNetwork &roads() const { return mRoads; }
      const std::vector<SceneObject> &objects() const { return mObjects; }
      const std::vector<GroundMark> &marks() const { return mMarks; }
      const Eigen::Vector3d &towardsSun() const { return mTowardsSun; }

      //! Whether a sample key is a control target: worth finer anti-aliasing (they are measured by centroid).
      static bool isControlTargetKey( uint32_t key );

      void setOrtho( std::shared_ptr<const OrthoTexture> ortho ) { mOrtho = std::move( ortho ); }

      /**
       * A fixed band limit for the ground textures, metres: every ray sees
       * the ground as if its footprint were this, so all images of a survey
       * see the same ground signal (aerial surveys, whose footprints hardly
       * differ: set it a little above the ground pixel size). 0 (default)
       * band-limits to each ray's own footprint, for scenes from a metre to
       * the horizon.
       */
      void setTextureFloorM( double floorM ) { mTextureFloorM = floorM; }

      /**
       * The colour seen along a unit ray. `pixelAngleRad` is the angle one
       * sample covers, for band-limiting the textures.
       */
      SurfaceSample trace( const Eigen::Vector3d &origin, const Eigen::Vector3d &direction, double pixelAngleRad ) const;

      /**
       * Whether `point` can be seen from `origin`: no terrain and no object
       * (other than `ownObject`, -1 for none) in between. Points on the
       * terrain surface count as seen when the terrain is met within
       * `toleranceM` of them.
       */
      bool isVisible( const Eigen::Vector3d &origin, const Eigen::Vector3d &point, int ownObject, double toleranceM = 0.02 ) const;

      //! Whether the ground at `xy` lies in an object's shadow.
      bool inShadow( const Eigen::Vector2d &xy ) const;

    private:
      //! `mark` receives the ground mark hit, if any (a flat board: shaded with one normal).
      Eigen::Vector3f groundAlbedo( const Eigen::Vector3d &p, double footprintM, uint32_t &key, const GroundMark **mark = nullptr ) const;
      //! Nearest object hit for t < tMax, skipping `ignore`; returns the object index or -1.
      int firstObjectHit( const Eigen::Vector3d &origin, const Eigen::Vector3d &direction, double tMax, int ignore, ObjectHit &hit ) const;

      HeightField mTerrain;
      RoadNetwork mRoads;
      std::vector<SceneObject> mObjects;
      std::vector<GroundMark> mMarks;
      std::vector<ShadowShape> mShadows;
      SpatialGrid mObjectGrid, mMarkGrid, mShadowGrid;
      double mObjectTop = -1e300; //!< highest point of any object
      std::vector<float> mObjectCellTop; //!< per object-grid cell: highest point of its objects
      Eigen::Vector3d mTowardsSun;
      double mAmbient;
      uint32_t mSeed;
      std::shared_ptr<const OrthoTexture> mOrtho;
      double mTextureFloorM = 0.0;
  };

} // namespace geostation

#endif // GEOSTATION_SIMULATION_SCENE_H

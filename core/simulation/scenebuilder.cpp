/***************************************************************************
  scenebuilder.cpp - terrain, roads, objects and targets of a simulated survey
  -------------------------------------------------------------------------
  Procedural roads, and SceneBuilder (the steps of buildScene()); what is
  read from files is in scenesources.cpp.
 ***************************************************************************/
#include "simulation/scenebuilder.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <random>
#include <sstream>
#include <stdexcept>

#include "dem/dem.h"
#include "geometry/crs.h"
#include "geometry/rotation.h"
#include "simulation/proceduralnoise.h"
#include "simulation/proceduralroads.h"
#include "simulation/scenesources.h"

namespace geostation
{
  namespace
  {
    constexpr double kSiteX = 500000.0, kSiteY = 4400000.0; //!< procedural sites: UTM 17N
    constexpr const char *kProceduralCrs = "EPSG:32617";

    double smoothstep( double edge0, double edge1, double x )
    {
      const double t = std::clamp( ( x - edge0 ) / ( edge1 - edge0 ), 0.0, 1.0 );
      return t * t * ( 3 - 2 * t );
    }

    /**
     * One scene built from a request, in named steps: openDem, placeRoads,
     * chooseTerrainGrid, estimateDemFallback, profileRoads, buildTerrain,
     * placeAlongRoad (per road) and placeInOpenField; finishScene hands
     * everything to the Scene. The random sequence of the placement is the
     * seed's, in this order.
     */
    class SceneBuilder
    {
      public:
        explicit SceneBuilder( const SceneRequest &request )
          : mRequest( request )
          , mRandom( request.seed * 7919u + 17u )
          , mJitter( -1.0, 1.0 ) {}

        BuiltScene build();

      private:
        void openDem();
        void placeRoads();
        void chooseTerrainGrid();
        double roadLevel( double x, double y ) const;
        double groundHeight( double x, double y ) const;
        void estimateDemFallback();
        void profileRoads();
        double roadZ( const RoadLocation &location ) const;
        void buildTerrain();
        bool freeSpot( const Eigen::Vector2d &p, double radius, int road, bool offRoad ) const;
        void addObject( ObjectKind kind, const std::string &id, const Eigen::Vector2d &p, double heading, const Eigen::Vector3f &colour );
        void addTarget( const Eigen::Vector2d &p );
        void placeAlongRoad( int road );
        void placeOnRoad( int road );
        void placeRoadTargets( int road );
        void placeInOpenField();
        void finishScene();
        static std::string numbered( const char *prefix, int n );

        const SceneRequest &mRequest;
        BuiltScene mBuilt;
        std::unique_ptr<Dem> mDem;
        std::unique_ptr<CrsTransform> mToDem;          //!< block CRS -> DEM CRS
        std::vector<Road> mRoads;
        Eigen::Vector2d mDemLo = Eigen::Vector2d::Zero(), mDemHi = Eigen::Vector2d::Zero(); //!< the DEM's extent in the block CRS
        Eigen::Vector2d mLo = Eigen::Vector2d::Zero(), mHi = Eigen::Vector2d::Zero();       //!< the terrain's extent
        double mSpacingM = 0.5;
        int mWidth = 0, mHeight = 0;                   //!< terrain nodes
        double mDemFallback = 0.0;                     //!< height where the DEM has none: its mean over the scene
        std::optional<RoadNetwork> mNetwork;
        std::vector<std::vector<double>> mProfiles;    //!< road heights every metre along each centre line
        std::optional<HeightField> mTerrain;
        std::mt19937 mRandom;
        std::uniform_real_distribution<double> mJitter;
        std::vector<SceneObject> mObjects;
        std::vector<GroundMark> mMarks;
        int mPoles = 0, mSigns = 0, mHydrants = 0, mTrees = 0, mCars = 0, mManholes = 0, mTargets = 0;
    };

    BuiltScene SceneBuilder::build()
    {
      openDem();
      placeRoads();
      chooseTerrainGrid();
      estimateDemFallback();
      mNetwork.emplace( mRoads );
      profileRoads();
      buildTerrain();
      for ( size_t r = 0; r < mRoads.size(); ++r )
      {
        placeAlongRoad( static_cast<int>( r ) );
        placeOnRoad( static_cast<int>( r ) );
        placeRoadTargets( static_cast<int>( r ) );
      }
      if ( mRequest.preset != SurveyPreset::Highway )
        placeInOpenField();
      finishScene();
      return std::move( mBuilt );
    }

    //! The DEM, if given, and the block CRS: the DEM's (projected) or the procedural site's.
    void SceneBuilder::openDem()
    {
      if ( mRequest.demPath.empty() )
      {
        mBuilt.crs = kProceduralCrs;
        return;
      }
      try
      {
        mDem = std::make_unique<Dem>( mRequest.demPath );
      }
      catch ( const std::exception &e )
      {
        throw std::invalid_argument( e.what() );
      }
      mBuilt.crs = blockCrsForDem( *mDem, mBuilt.notes );
      demExtentInBlock( *mDem, mBuilt.crs, mDemLo, mDemHi );
    }

    //! Roads from the layer (they must overlap the DEM) or procedural ones; the site centre.
    void SceneBuilder::placeRoads()
    {
      if ( mRequest.roadsPath.empty() )
      {
        mBuilt.siteCentre = mDem ? Eigen::Vector2d( 0.5 * ( mDemLo + mDemHi ) ) : Eigen::Vector2d( kSiteX, kSiteY );
        mRoads = proceduralRoads( mRequest.preset, mBuilt.siteCentre );
        return;
      }
      mRoads = loadRoads( mRequest.roadsPath, mBuilt.crs, mBuilt.notes );
      Eigen::Vector2d lo = mRoads.front().centreline.front(), hi = lo;
      for ( const Eigen::Vector2d &p : mRoads.front().centreline )
      {
        lo = lo.cwiseMin( p );
        hi = hi.cwiseMax( p );
      }
      mBuilt.siteCentre = mRequest.preset == SurveyPreset::Highway ? mRoads.front().centreline.front() : 0.5 * ( lo + hi );
      if ( mDem && ( hi.x() < mDemLo.x() || lo.x() > mDemHi.x() || hi.y() < mDemLo.y() || lo.y() > mDemHi.y() ) )
        throw std::invalid_argument( "the road layer does not overlap the DEM (roads " + sceneNumber( lo.x() ) + ", " + sceneNumber( lo.y() ) + " to " + sceneNumber( hi.x() ) +
                                     ", " + sceneNumber( hi.y() ) + ", DEM " + sceneNumber( mDemLo.x() ) + ", " + sceneNumber( mDemLo.y() ) + " to " +
                                     sceneNumber( mDemHi.x() ) + ", " + sceneNumber( mDemHi.y() ) + " in the block CRS)" );
    }

    //! The terrain extent (the request around the site centre, inside the DEM) and its nodes (at most 30 million).
    void SceneBuilder::chooseTerrainGrid()
    {
      mLo = mBuilt.siteCentre + mRequest.extentMin;
      mHi = mBuilt.siteCentre + mRequest.extentMax;
      if ( mDem )
      {
        mLo = mLo.cwiseMax( mDemLo );
        mHi = mHi.cwiseMin( mDemHi );
        if ( !( mLo.x() < mHi.x() && mLo.y() < mHi.y() ) )
          throw std::invalid_argument( "the DEM does not overlap the scene" );
      }
      mSpacingM = mRequest.nodeSpacingM;
      while ( ( mHi.x() - mLo.x() ) / mSpacingM * ( mHi.y() - mLo.y() ) / mSpacingM > 30e6 )
        mSpacingM *= 1.5;
      if ( mSpacingM != mRequest.nodeSpacingM )
        mBuilt.notes.push_back( "terrain nodes every " + sceneNumber( mSpacingM ) + " m to keep the grid under 30 million nodes" );
      mWidth = static_cast<int>( std::floor( ( mHi.x() - mLo.x() ) / mSpacingM ) ) + 1;
      mHeight = static_cast<int>( std::floor( ( mHi.y() - mLo.y() ) / mSpacingM ) ) + 1;
      if ( mWidth < 8 || mHeight < 8 )
        throw std::invalid_argument( "the DEM covers too little of the scene (under 8 x 8 terrain nodes)" );
      if ( mDem )
        mToDem = std::make_unique<CrsTransform>( mBuilt.crs, mDem->crsWkt() );
    }

    //! The smooth surface procedural roads follow.
    double SceneBuilder::roadLevel( double x, double y ) const
    {
      const double lx = x - mBuilt.siteCentre.x(), ly = y - mBuilt.siteCentre.y();
      return 200.0 + 0.012 * lx + 0.006 * ly + 2.0 * std::sin( lx / 170.0 ) * std::cos( ly / 230.0 );
    }

    //! The ground before the roads are cut in: the DEM's (NaN where it has none), or procedural hills.
    double SceneBuilder::groundHeight( double x, double y ) const
    {
      if ( mDem )
      {
        const Eigen::Vector3d p = mToDem->transform( Eigen::Vector3d( x, y, 0.0 ) );
        const std::optional<double> h = mDem->heightAt( p.x(), p.y() );
        return h ? *h : std::numeric_limits<double>::quiet_NaN();
      }
      const double hillAmplitude = mRequest.preset == SurveyPreset::ObliquePhoto ? 22.0 : ( mRequest.preset == SurveyPreset::AerialStereo ? 8.0 : 6.0 );
      const double lx = x - mBuilt.siteCentre.x(), ly = y - mBuilt.siteCentre.y();
      const double hills = std::sin( lx / 55.0 + 1.3 ) * std::cos( ly / 70.0 ) + 0.7 * noise::fbm( lx, ly, 120.0, 3, 1.0, mRequest.seed + 101 );
      return roadLevel( x, y ) + hillAmplitude * hills;
    }

    //! The DEM's mean height over 8 x 8 samples of the scene, for where it has none.
    void SceneBuilder::estimateDemFallback()
    {
      if ( !mDem )
        return;
      double sum = 0.0;
      int count = 0;
      for ( int k = 0; k < 64; ++k )
        if ( const double h = groundHeight( mLo.x() + ( mHi.x() - mLo.x() ) * ( k % 8 + 0.5 ) / 8, mLo.y() + ( mHi.y() - mLo.y() ) * ( k / 8 + 0.5 ) / 8 ); std::isfinite( h ) )
        {
          sum += h;
          ++count;
        }
      if ( count == 0 )
        throw std::invalid_argument( "the DEM has no heights where the scene is" );
      mDemFallback = sum / count;
    }

    //! Road height profiles: the ground along the centre line, smoothed over +-15 m; side roads meet the road they join.
    void SceneBuilder::profileRoads()
    {
      const RoadNetwork &network = *mNetwork;
      mProfiles.resize( mRoads.size() );
      for ( size_t r = 0; r < mRoads.size(); ++r )
      {
        const int n = static_cast<int>( std::ceil( network.length( static_cast<int>( r ) ) ) ) + 1;
        std::vector<double> raw( n );
        for ( int k = 0; k < n; ++k )
        {
          const Eigen::Vector2d p = network.pointAt( static_cast<int>( r ), k, 0.0 );
          double h = mDem ? groundHeight( p.x(), p.y() ) : roadLevel( p.x(), p.y() );
          raw[k] = std::isfinite( h ) ? h : std::numeric_limits<double>::quiet_NaN();
        }
        std::vector<double> &profile = mProfiles[r];
        profile.resize( n );
        for ( int k = 0; k < n; ++k )
        {
          double sum = 0.0;
          int count = 0;
          for ( int m = std::max( 0, k - 15 ); m <= std::min( n - 1, k + 15 ); ++m )
            if ( std::isfinite( raw[m] ) )
            {
              sum += raw[m];
              ++count;
            }
          profile[k] = count ? sum / count : mDemFallback;
        }
        for ( size_t q = 0; q < r; ++q )
          for ( int k = 0; k < n; ++k )
          {
            const Eigen::Vector2d p = network.pointAt( static_cast<int>( r ), k, 0.0 );
            const std::optional<RoadLocation> other = network.nearestCentreline( p.x(), p.y(), 1e9 );
            if ( !other || other->road != static_cast<int>( q ) )
              continue;
            const double reach = mRoads[q].halfWidthM() + 25.0;
            const double w = smoothstep( mRoads[q].halfWidthM(), reach, std::abs( other->d ) );
            const double sq = std::clamp( other->s, 0.0, static_cast<double>( mProfiles[q].size() - 1 ) );
            const double target = mProfiles[q][static_cast<size_t>( std::lround( sq ) )];
            profile[k] = ( 1 - w ) * target + w * profile[k];
          }
      }
    }

    //! The road's height at a location on it, from its profile.
    double SceneBuilder::roadZ( const RoadLocation &location ) const
    {
      const std::vector<double> &profile = mProfiles[location.road];
      const double s = std::clamp( location.s, 0.0, static_cast<double>( profile.size() - 1 ) );
      const size_t k = std::min( static_cast<size_t>( s ), profile.size() - 2 );
      const double f = s - k;
      return ( 1 - f ) * profile[k] + f * profile[k + 1];
    }

    //! The terrain: the ground with the roads cut in, blended into it beyond the kerbs and shoulders.
    void SceneBuilder::buildTerrain()
    {
      long filled = 0;
      mTerrain.emplace( mLo.x(), mHi.y(), mSpacingM, mWidth, mHeight, [&]( double x, double y )
      {
        double g = groundHeight( x, y );
        if ( !std::isfinite( g ) )
        {
          ++filled;
          g = mDemFallback;
        }
        const std::optional<RoadLocation> location = mNetwork->nearestCentreline( x, y, 1e9 );
        if ( !location )
          return g;
        const Road &road = mRoads[location->road];
        const double edge = road.halfWidthM() + kKerbWidthM + kShoulderWidthM;
        const double w = smoothstep( edge, edge + kBlendReachM, std::abs( location->d ) );
        return ( 1 - w ) * roadZ( *location ) + w * g;
      } );
      if ( filled > 0 )
        mBuilt.notes.push_back( std::to_string( filled ) + " terrain nodes outside the DEM's data took its mean height" );
      if ( mDem && mDem->filledCellCount() > 0 )
        mBuilt.notes.push_back( std::to_string( mDem->filledCellCount() ) + " DEM cells without data were filled from their neighbours" );
    }

    //! On the terrain, on the given road (or off every road), clear of everything placed so far.
    bool SceneBuilder::freeSpot( const Eigen::Vector2d &p, double radius, int road, bool offRoad ) const
    {
      if ( !mTerrain->covers( p.x(), p.y() ) )
        return false;
      const std::optional<RoadLocation> at = mNetwork->locate( p.x(), p.y() );
      if ( offRoad && at )
        return false;
      if ( !offRoad && ( !at || at->road != road ) )
        return false;
      for ( const SceneObject &o : mObjects )
        if ( ( o.base.head<2>() - p ).norm() < radius + o.footprintRadiusM() + 0.3 )
          return false;
      for ( const GroundMark &m : mMarks )
        if ( ( m.centre.head<2>() - p ).norm() < radius + m.reachM() + 0.3 )
          return false;
      return true;
    }

    void SceneBuilder::addObject( ObjectKind kind, const std::string &id, const Eigen::Vector2d &p, double heading, const Eigen::Vector3f &colour )
    {
      SceneObject o;
      o.id = id;
      o.kind = kind;
      o.base = Eigen::Vector3d( p.x(), p.y(), *mTerrain->heightAt( p.x(), p.y() ) );
      o.headingRad = heading;
      o.colour = colour;
      mObjects.push_back( o );
    }

    //! A signalised control target: a white disc on a black square.
    void SceneBuilder::addTarget( const Eigen::Vector2d &p )
    {
      GroundMark m;
      m.id = numbered( "GCP", ++mTargets );
      m.kind = GroundMarkKind::Target;
      m.centre = Eigen::Vector3d( p.x(), p.y(), *mTerrain->heightAt( p.x(), p.y() ) );
      m.radiusM = mRequest.targetRadiusM;
      m.squareHalfM = 1.6 * mRequest.targetRadiusM;
      mMarks.push_back( m );
    }

    std::string SceneBuilder::numbered( const char *prefix, int n )
    {
      char buffer[32];
      std::snprintf( buffer, sizeof buffer, "%s%03d", prefix, n );
      return std::string( buffer );
    }

    //! Beside the road: poles (alternating sides every 30 m), signs, hydrants and trees.
    void SceneBuilder::placeAlongRoad( int ri )
    {
      const RoadNetwork &network = *mNetwork;
      const double length = network.length( ri );
      const double outside = mRoads[ri].halfWidthM() + kKerbWidthM;
      Eigen::Vector2d tangent;
      for ( double s = 12.0; s < length; s += 30.0 )
      {
        const double side = ( static_cast<int>( s / 30.0 ) % 2 ) ? 1.0 : -1.0;
        const Eigen::Vector2d p = network.pointAt( ri, s + 2.0 * mJitter( mRandom ), side * ( outside + kShoulderWidthM + 0.6 ), &tangent );
        if ( freeSpot( p, 0.2, ri, true ) )
          addObject( ObjectKind::Pole, numbered( "pole_", ++mPoles ), p, 0.0, Eigen::Vector3f( 0.62f, 0.63f, 0.66f ) );
      }
      for ( double s = 25.0; s < length; s += 70.0 )
      {
        const Eigen::Vector2d p = network.pointAt( ri, s, -( outside + 0.8 ), &tangent );
        if ( freeSpot( p, 0.5, ri, false ) )
          addObject( ObjectKind::Sign, numbered( "sign_", ++mSigns ), p, std::atan2( -tangent.y(), -tangent.x() ), Eigen::Vector3f::Zero() );
      }
      for ( double s = 40.0; s < length; s += 55.0 )
      {
        const Eigen::Vector2d p = network.pointAt( ri, s, outside + 1.0, &tangent );
        if ( freeSpot( p, 0.3, ri, false ) )
          addObject( ObjectKind::Hydrant, numbered( "hydrant_", ++mHydrants ), p, 0.0, Eigen::Vector3f( 0.8f, 0.12f, 0.08f ) );
      }
      for ( double s = 8.0; s < length; s += 14.0 )
        for ( double side : { -1.0, 1.0 } )
        {
          const Eigen::Vector2d p = network.pointAt( ri, s + 4.0 * mJitter( mRandom ), side * ( outside + kShoulderWidthM + 4.0 + 3.0 * std::abs( mJitter( mRandom ) ) ) );
          if ( mJitter( mRandom ) > -0.2 && freeSpot( p, 2.3, ri, true ) )
            addObject( ObjectKind::Tree, numbered( "tree_", ++mTrees ), p, 0.0, Eigen::Vector3f( 0.16f, 0.3f, 0.1f ) * static_cast<float>( 1.0 + 0.2 * mJitter( mRandom ) ) );
        }
    }

    //! On the road: parked cars at the kerb and manhole lids in the lane (not where a road of higher priority crosses).
    void SceneBuilder::placeOnRoad( int ri )
    {
      static const Eigen::Vector3f carColours[] = { { 0.7f, 0.1f, 0.1f }, { 0.15f, 0.25f, 0.6f }, { 0.85f, 0.85f, 0.85f }, { 0.1f, 0.1f, 0.1f }, { 0.5f, 0.5f, 0.45f } };
      const RoadNetwork &network = *mNetwork;
      const double length = network.length( ri );
      Eigen::Vector2d tangent;
      for ( double s = 60.0; s < length; s += 65.0 )
      {
        const Eigen::Vector2d p = network.pointAt( ri, s, mRoads[ri].halfWidthM() - 1.05, &tangent );
        if ( freeSpot( p, 2.4, ri, false ) && !network.onHigherPriorityRoad( ri, p.x(), p.y() ) )
        {
          const std::string carId = numbered( "car_", ++mCars );
          addObject( ObjectKind::Car, carId, p, std::atan2( tangent.y(), tangent.x() ) + kPi, carColours[mCars % 5] );
        }
      }
      for ( double s = 30.0; s < length; s += 45.0 )
      {
        const Eigen::Vector2d p = network.pointAt( ri, s, -0.5 * mRoads[ri].laneWidthM + 0.9, &tangent );
        if ( freeSpot( p, 0.35, ri, false ) && !network.onHigherPriorityRoad( ri, p.x(), p.y() ) )
        {
          GroundMark m;
          m.id = numbered( "manhole_", ++mManholes );
          m.kind = GroundMarkKind::Manhole;
          m.centre = Eigen::Vector3d( p.x(), p.y(), *mTerrain->heightAt( p.x(), p.y() ) );
          m.radiusM = 0.32;
          mMarks.push_back( m );
        }
      }
    }

    //! Control targets on the shoulders, alternating sides (every 20 m on the highway; in the aerial scenes spaced by their size).
    void SceneBuilder::placeRoadTargets( int ri )
    {
      const bool highway = mRequest.preset == SurveyPreset::Highway;
      const double targetRadius = mRequest.targetRadiusM;
      const double length = mNetwork->length( ri );
      const double outside = mRoads[ri].halfWidthM() + kKerbWidthM;
      const double targetSpacing = highway ? 20.0 : std::max( 25.0, 60.0 * targetRadius );
      for ( double s = 15.0; s < length; s += targetSpacing )
      {
        const double side = ( static_cast<int>( s / targetSpacing ) % 2 ) ? 1.0 : -1.0;
        const double half = 1.6 * targetRadius;
        const Eigen::Vector2d p = mNetwork->pointAt( ri, s, side * ( outside + std::max( 0.5 * kShoulderWidthM, half + 0.1 ) ) );
        if ( freeSpot( p, half * 1.5, ri, !highway ) || ( highway && freeSpot( p, half * 1.5, ri, false ) ) )
          addTarget( p );
      }
    }

    //! Open-field targets and trees for the aerial and oblique scenes.
    void SceneBuilder::placeInOpenField()
    {
      std::uniform_real_distribution<double> ux( mLo.x() + 5, mHi.x() - 5 ), uy( mLo.y() + 5, mHi.y() - 5 );
      const double targetRadius = mRequest.targetRadiusM;
      const double area = ( mHi.x() - mLo.x() ) * ( mHi.y() - mLo.y() );
      const int fieldTargets = std::clamp( static_cast<int>( area / ( 5000.0 * targetRadius * targetRadius ) ), 8, 60 );
      for ( int k = 0, tries = 0; k < fieldTargets && tries < 20 * fieldTargets; ++tries )
      {
        const Eigen::Vector2d p( ux( mRandom ), uy( mRandom ) );
        const double half = 1.6 * targetRadius;
        if ( !freeSpot( p, half * 1.5, -1, true ) )
          continue;
        addTarget( p );
        ++k;
      }
      const int fieldTrees = std::clamp( static_cast<int>( area / ( mRequest.preset == SurveyPreset::ObliquePhoto ? 4000.0 : 1500.0 ) ), 10, 3000 );
      for ( int k = 0, tries = 0; k < fieldTrees && tries < 10 * fieldTrees; ++tries )
      {
        const Eigen::Vector2d p( ux( mRandom ), uy( mRandom ) );
        if ( !freeSpot( p, 2.3, -1, true ) )
          continue;
        addObject( ObjectKind::Tree, numbered( "tree_", ++mTrees ), p, 0.0, Eigen::Vector3f( 0.16f, 0.3f, 0.1f ) * static_cast<float>( 1.0 + 0.2 * mJitter( mRandom ) ) );
        ++k;
      }
    }

    //! The scene from the terrain, roads, objects and marks; the orthophoto's texture if one is given.
    void SceneBuilder::finishScene()
    {
      mBuilt.scene = std::make_unique<Scene>( std::move( *mTerrain ), std::move( *mNetwork ), std::move( mObjects ), std::move( mMarks ), SceneLighting(), mRequest.seed );
      mBuilt.scene->setTextureFloorM( mRequest.textureFloorM );
      if ( !mRequest.orthoPath.empty() )
      {
        mBuilt.scene->setOrtho( loadOrtho( mRequest.orthoPath, mBuilt.crs, mLo, mHi ) );
        mBuilt.notes.push_back( "ground texture from the orthophoto " + mRequest.orthoPath );
      }
    }
  } // namespace

  std::string surveyPresetName( SurveyPreset preset )
  {
    switch ( preset )
    {
      case SurveyPreset::Highway:
        return "highway";
      case SurveyPreset::AerialStereo:
        return "aerial_stereo";
      case SurveyPreset::ObliquePhoto:
        return "oblique_photo";
    }
    return "highway";
  }

  SurveyPreset surveyPresetFromName( const std::string &name )
  {
    for ( SurveyPreset preset : { SurveyPreset::Highway, SurveyPreset::AerialStereo, SurveyPreset::ObliquePhoto } )
      if ( surveyPresetName( preset ) == name )
        return preset;
    throw std::invalid_argument( "unknown preset \"" + name + "\": use highway, aerial_stereo or oblique_photo" );
  }

  BuiltScene buildScene( const SceneRequest &request )
  {
    return SceneBuilder( request ).build();
  }

} // namespace geostation

/***************************************************************************
  scene.cpp - ray tracing and shading of the simulated world
 ***************************************************************************/
#include "simulation/scene.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "geometry/rotation.h"
#include "simulation/proceduralnoise.h"

namespace geostation
{
  namespace
  {
    enum Material : uint32_t
    {
      Sky = 0, Grass, Soil, Gravel, Asphalt, Paint, Kerb, Manhole, TargetWhite, TargetBlack, Object, Ortho
    };

    uint32_t makeKey( uint32_t material, bool shadow, int object = -1, int part = 0 )
    {
      return ( material << 27 ) | ( shadow ? 1u << 26 : 0u ) | ( ( static_cast<uint32_t>( object + 1 ) & 0x7FFFFu ) << 3 ) | ( static_cast<uint32_t>( part ) & 7u );
    }

    Eigen::Vector3f mix( const Eigen::Vector3f &a, const Eigen::Vector3f &b, double w )
    {
      return a + ( b - a ) * static_cast<float>( std::clamp( w, 0.0, 1.0 ) );
    }
  }

  Scene::Scene( HeightField terrain, RoadNetwork roads, std::vector<SceneObject> objects, std::vector<GroundMark> marks,
                const SceneLighting &lighting, uint32_t seed )
    : mTerrain( std::move( terrain ) )
    , mRoads( std::move( roads ) )
    , mObjects( std::move( objects ) )
    , mMarks( std::move( marks ) )
    , mAmbient( lighting.ambient )
    , mSeed( seed )
  {
    const double az = degToRad( lighting.sunAzimuthDeg ), el = degToRad( lighting.sunElevationDeg );
    mTowardsSun = Eigen::Vector3d( std::sin( az ) * std::cos( el ), std::cos( az ) * std::cos( el ), std::sin( el ) );

    const Eigen::Vector2d lo( mTerrain.originX(), mTerrain.originY() - ( mTerrain.height() - 1 ) * mTerrain.spacing() );
    const Eigen::Vector2d hi( mTerrain.originX() + ( mTerrain.width() - 1 ) * mTerrain.spacing(), mTerrain.originY() );
    mObjectGrid = SpatialGrid( lo, hi, 4.0 );
    mMarkGrid = SpatialGrid( lo, hi, 4.0 );
    mShadowGrid = SpatialGrid( lo, hi, 4.0 );
    for ( size_t i = 0; i < mObjects.size(); ++i )
    {
      const SceneObject &object = mObjects[i];
      const Eigen::Vector2d r = Eigen::Vector2d::Constant( object.footprintRadiusM() );
      mObjectGrid.insert( static_cast<int>( i ), object.base.head<2>() - r, object.base.head<2>() + r );
      mObjectTop = std::max( mObjectTop, object.base.z() + object.heightM() );
      for ( const ShadowShape &shape : objectShadows( object, mTowardsSun ) )
      {
        mShadows.push_back( shape );
        mShadowGrid.insert( static_cast<int>( mShadows.size() - 1 ), shape.boxMin, shape.boxMax );
      }
    }
    mObjectCellTop.assign( static_cast<size_t>( mObjectGrid.cellsX() ) * mObjectGrid.cellsY(), -std::numeric_limits<float>::infinity() );
    for ( int j = 0; j < mObjectGrid.cellsY(); ++j )
      for ( int i = 0; i < mObjectGrid.cellsX(); ++i )
        for ( int item : mObjectGrid.cell( i, j ) )
        {
          float &top = mObjectCellTop[static_cast<size_t>( j ) * mObjectGrid.cellsX() + i];
          top = std::max( top, static_cast<float>( mObjects[item].base.z() + mObjects[item].heightM() ) );
        }
    for ( size_t i = 0; i < mMarks.size(); ++i )
    {
      const Eigen::Vector2d r = Eigen::Vector2d::Constant( mMarks[i].reachM() );
      mMarkGrid.insert( static_cast<int>( i ), mMarks[i].centre.head<2>() - r, mMarks[i].centre.head<2>() + r );
    }
  }

  bool Scene::isControlTargetKey( uint32_t key )
  {
    const uint32_t material = key >> 27;
    return material == TargetWhite || material == TargetBlack;
  }

  bool Scene::inShadow( const Eigen::Vector2d &xy ) const
  {
    for ( int item : mShadowGrid.at( xy.x(), xy.y() ) )
      if ( mShadows[item].contains( xy ) )
        return true;
    return false;
  }

  Eigen::Vector3f Scene::groundAlbedo( const Eigen::Vector3d &p, double footprintM, uint32_t &key, const GroundMark **markHit ) const
  {
    const double x = p.x(), y = p.y();
    // Ground marks first: they lie on top of everything.
    for ( int item : mMarkGrid.at( x, y ) )
    {
      const GroundMark &mark = mMarks[item];
      const Eigen::Vector2d rel = p.head<2>() - mark.centre.head<2>();
      if ( mark.kind == GroundMarkKind::Target )
      {
        if ( markHit && ( rel.squaredNorm() <= mark.radiusM * mark.radiusM || ( std::abs( rel.x() ) <= mark.squareHalfM && std::abs( rel.y() ) <= mark.squareHalfM ) ) )
          *markHit = &mark;
        if ( rel.squaredNorm() <= mark.radiusM * mark.radiusM )
        {
          key = TargetWhite;
          return Eigen::Vector3f::Constant( 0.95f );
        }
        if ( std::abs( rel.x() ) <= mark.squareHalfM && std::abs( rel.y() ) <= mark.squareHalfM )
        {
          key = TargetBlack;
          return Eigen::Vector3f::Constant( 0.04f );
        }
      }
      else if ( rel.squaredNorm() <= mark.radiusM * mark.radiusM )
      {
        // cast-iron lid with a ring and a chequer of ribs
        const double r = rel.norm();
        const bool rib = r > mark.radiusM - 0.04 || ( ( static_cast<int>( std::floor( rel.x() / 0.06 ) ) + static_cast<int>( std::floor( rel.y() / 0.06 ) ) ) & 1 );
        key = Manhole;
        return Eigen::Vector3f::Constant( rib ? 0.16f : 0.24f );
      }
    }
    if ( mOrtho )
    {
      const double col = ( x - mOrtho->originX ) / mOrtho->pixelSizeM - 0.5, row = ( mOrtho->originY - y ) / mOrtho->pixelSizeM - 0.5;
      if ( col >= 0 && row >= 0 && col < mOrtho->rgb.cols - 1 && row < mOrtho->rgb.rows - 1 )
      {
        const int c0 = static_cast<int>( col ), r0 = static_cast<int>( row );
        const float u = static_cast<float>( col - c0 ), v = static_cast<float>( row - r0 );
        Eigen::Vector3f sum = Eigen::Vector3f::Zero();
        const float w[4] = { ( 1 - u ) * ( 1 - v ), u * ( 1 - v ), ( 1 - u ) * v, u * v };
        const cv::Vec3b *rowA = mOrtho->rgb.ptr<cv::Vec3b>( r0 ), *rowB = mOrtho->rgb.ptr<cv::Vec3b>( r0 + 1 );
        const cv::Vec3b px[4] = { rowA[c0], rowA[c0 + 1], rowB[c0], rowB[c0 + 1] };
        for ( int k = 0; k < 4; ++k )
          sum += w[k] * Eigen::Vector3f( px[k][0], px[k][1], px[k][2] ) / 255.0f;
        key = Ortho;
        return sum;
      }
    }
    // detail from 2 m down to millimetres with slowly falling amplitude, so every
    // scale an image resolves has texture to match on
    const double fine = noise::fbm( x, y, 2.0, 9, footprintM, mSeed + 11, 1.0 );
    if ( const std::optional<RoadLocation> location = mRoads.locate( x, y ) )
    {
      const Road &road = mRoads.roads()[location->road];
      const double ad = std::abs( location->d );
      if ( ad <= road.halfWidthM() )
      {
        const double coarse = noise::fbm( x, y, 6.0, 3, footprintM, mSeed + 12 );
        const float grey = static_cast<float>( 0.27 + 0.1 * fine + 0.03 * coarse );
        key = Asphalt;
        Eigen::Vector3f colour( grey, grey, grey * 1.02f );
        if ( location->road == 0 || !mRoads.onHigherPriorityRoad( location->road, x, y ) )
        {
          for ( const RoadMarkingLine &line : mRoads.markings( location->road ) )
          {
            if ( std::abs( location->d - line.offsetM ) > 0.5 * line.widthM )
              continue;
            if ( line.dashed && std::fmod( location->s, kDashM + kGapM ) > kDashM )
              continue;
            // worn paint: patches where the asphalt shows through
            const double wear = noise::fbm( x, y, 0.35, 3, footprintM, mSeed + 13 );
            if ( wear < -0.45 )
              continue;
            key = Paint;
            const float paint = static_cast<float>( 0.82 + 0.05 * fine - 0.15 * std::clamp( -wear, 0.0, 1.0 ) );
            colour = Eigen::Vector3f( paint, paint, paint * 0.97f );
          }
        }
        return colour;
      }
      if ( ad <= road.halfWidthM() + kKerbWidthM )
      {
        key = Kerb;
        const float grey = static_cast<float>( 0.6 + 0.04 * fine );
        return Eigen::Vector3f( grey, grey, grey * 0.98f );
      }
      const double grit = noise::fbm( x, y, 0.12, 4, footprintM, mSeed + 14 );
      key = Gravel;
      const float grey = static_cast<float>( 0.46 + 0.16 * grit + 0.05 * fine );
      return Eigen::Vector3f( grey * 1.04f, grey, grey * 0.9f );
    }
    // fields: grass and bare soil in patches
    const double patch = noise::fbm( x, y, 30.0, 3, footprintM, mSeed + 15 );
    const double blade = noise::fbm( x, y, 0.3, 5, footprintM, mSeed + 16 );
    const Eigen::Vector3f grass = Eigen::Vector3f( 0.22f, 0.38f, 0.14f ) * static_cast<float>( std::max( 0.1, 1.0 + 0.25 * blade + 0.75 * fine ) );
    const Eigen::Vector3f soil = Eigen::Vector3f( 0.42f, 0.33f, 0.22f ) * static_cast<float>( std::max( 0.1, 1.0 + 0.7 * fine ) );
    const double w = std::clamp( ( patch - 0.2 ) / 0.15, 0.0, 1.0 );
    key = Grass; // grass and soil blend smoothly: no edge to anti-alias
    return mix( grass, soil, w );
  }

  int Scene::firstObjectHit( const Eigen::Vector3d &origin, const Eigen::Vector3d &direction, double tMax, int ignore, ObjectHit &hit ) const
  {
    if ( mObjects.empty() )
      return -1;
    // only the part of the ray below the highest object top can meet an object
    double ta = 0.0, tb = tMax;
    if ( direction.z() < 0.0 )
      ta = std::max( ta, ( mObjectTop - origin.z() ) / direction.z() );
    else if ( direction.z() > 0.0 )
      tb = std::min( tb, ( mObjectTop - origin.z() ) / direction.z() );
    else if ( origin.z() > mObjectTop )
      return -1;
    // clip to the grid
    const Eigen::Vector2d lo = mObjectGrid.minimum();
    const double cell = mObjectGrid.cellSize();
    const Eigen::Vector2d hi = lo + Eigen::Vector2d( mObjectGrid.cellsX(), mObjectGrid.cellsY() ) * cell;
    for ( int k = 0; k < 2; ++k )
    {
      if ( std::abs( direction[k] ) < 1e-15 )
      {
        if ( origin[k] < lo[k] || origin[k] > hi[k] )
          return -1;
        continue;
      }
      double t0 = ( lo[k] - origin[k] ) / direction[k], t1 = ( hi[k] - origin[k] ) / direction[k];
      if ( t0 > t1 )
        std::swap( t0, t1 );
      ta = std::max( ta, t0 );
      tb = std::min( tb, t1 );
    }
    if ( !( ta <= tb ) )
      return -1;

    const Eigen::Vector2d p = ( origin.head<2>() + direction.head<2>() * ta - lo ) / cell;
    int ci = std::clamp( static_cast<int>( std::floor( p.x() ) ), 0, mObjectGrid.cellsX() - 1 );
    int cj = std::clamp( static_cast<int>( std::floor( p.y() ) ), 0, mObjectGrid.cellsY() - 1 );
    const int sx = direction.x() > 0 ? 1 : -1, sy = direction.y() > 0 ? 1 : -1;
    const double inf = std::numeric_limits<double>::infinity();
    double tx = direction.x() != 0 ? ta + ( ( ci + ( sx > 0 ) ) - p.x() ) * cell / direction.x() : inf;
    double ty = direction.y() != 0 ? ta + ( ( cj + ( sy > 0 ) ) - p.y() ) * cell / direction.y() : inf;
    const double dx = direction.x() != 0 ? cell / std::abs( direction.x() ) : inf;
    const double dy = direction.y() != 0 ? cell / std::abs( direction.y() ) : inf;
    int best = -1;
    double bestT = tMax;
    double tCell = ta;
    while ( true )
    {
      const double tNext = std::min( tx, ty );
      const double zMin = std::min( origin.z() + direction.z() * tCell, origin.z() + direction.z() * std::min( tNext, tb ) );
      // a cell whose objects all stand below the ray is skipped
      if ( zMin <= mObjectCellTop[static_cast<size_t>( cj ) * mObjectGrid.cellsX() + ci] )
      {
        for ( int item : mObjectGrid.cell( ci, cj ) )
        {
          if ( item == ignore )
            continue;
          ObjectHit candidate;
          if ( intersectObject( mObjects[item], origin, direction, bestT, candidate ) && candidate.t < bestT )
          {
            bestT = candidate.t;
            best = item;
            hit = candidate;
          }
        }
      }
      if ( tNext >= tb || bestT <= tNext )
        break;
      tCell = tNext;
      if ( tx < ty )
      {
        ci += sx;
        tx += dx;
      }
      else
      {
        cj += sy;
        ty += dy;
      }
      if ( ci < 0 || cj < 0 || ci >= mObjectGrid.cellsX() || cj >= mObjectGrid.cellsY() )
        break;
    }
    return best;
  }

  SurfaceSample Scene::trace( const Eigen::Vector3d &origin, const Eigen::Vector3d &direction, double pixelAngleRad ) const
  {
    SurfaceSample sample;
    const std::optional<TerrainHit> ground = mTerrain.intersect( origin, direction );
    const double tGround = ground ? ground->t : 1e7;
    ObjectHit objectHit;
    const int object = firstObjectHit( origin, direction, tGround, -1, objectHit );
    const auto lightAt = [&]( const Eigen::Vector3d &normal, bool shadow )
    {
      const double direct = shadow ? 0.0 : std::max( 0.0, normal.dot( mTowardsSun ) );
      return static_cast<float>( mAmbient + ( 1.0 - mAmbient ) * direct * 1.25 );
    };
    if ( object >= 0 )
    {
      Eigen::Vector3d normal = objectHit.normal;
      if ( normal.dot( direction ) > 0 )
        normal = -normal;
      sample.sky = false;
      sample.t = objectHit.t;
      sample.rgb = objectHit.albedo * lightAt( normal, false );
      sample.key = makeKey( Object, false, object, objectHit.part );
      return sample;
    }
    if ( ground )
    {
      const double cosIncidence = std::max( 0.15, std::abs( ground->normal.dot( direction ) ) );
      const double footprintM = mTextureFloorM > 0.0 ? mTextureFloorM : ground->t * pixelAngleRad / cosIncidence;
      uint32_t material = 0;
      const GroundMark *mark = nullptr;
      const Eigen::Vector3f albedo = groundAlbedo( ground->point, footprintM, material, &mark );
      const bool shadow = inShadow( ground->point.head<2>() );
      const Eigen::Vector3d normal = mark ? mTerrain.normalAt( mark->centre.x(), mark->centre.y() ) : ground->normal;
      sample.sky = false;
      sample.ground = true;
      sample.t = ground->t;
      sample.rgb = albedo * lightAt( normal, shadow );
      sample.key = makeKey( material, shadow );
      return sample;
    }
    // sky: brighter towards the horizon
    const double elevation = std::clamp( direction.z(), 0.0, 1.0 );
    sample.rgb = mix( Eigen::Vector3f( 0.86f, 0.89f, 0.93f ), Eigen::Vector3f( 0.42f, 0.58f, 0.86f ), std::sqrt( elevation ) );
    sample.key = makeKey( Sky, false );
    return sample;
  }

  bool Scene::isVisible( const Eigen::Vector3d &origin, const Eigen::Vector3d &point, int ownObject, double toleranceM ) const
  {
    const Eigen::Vector3d delta = point - origin;
    const double range = delta.norm();
    if ( range <= 0.0 )
      return true;
    const Eigen::Vector3d direction = delta / range;
    const double limit = range - toleranceM;
    if ( const std::optional<TerrainHit> ground = mTerrain.intersect( origin, direction, 0.0, limit ) )
      if ( ground->t < limit )
        return false;
    ObjectHit hit;
    return firstObjectHit( origin, direction, limit, ownObject, hit ) < 0;
  }

} // namespace geostation

/***************************************************************************
  sceneobjects.cpp - ray tests and shadows of the simulator's objects
 ***************************************************************************/
#include "simulation/sceneobjects.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace geostation
{
  namespace
  {
    // Dimensions in metres.
    constexpr double kPoleRadius = 0.08, kPoleHeight = 6.0;
    constexpr double kSignPostRadius = 0.035, kSignCentreHeight = 2.3, kSignRadius = 0.35, kSignOffset = 0.05;
    constexpr double kHydrantRadius = 0.12, kHydrantHeight = 0.6, kHydrantCapRadius = 0.09, kHydrantCapHeight = 0.75;
    constexpr double kTrunkRadius = 0.15, kTrunkHeight = 3.2, kCrownRadius = 2.2, kCrownHeight = 4.8;
    constexpr double kCarHalfLength = 2.2, kCarHalfWidth = 0.9, kCarHalfHeight = 0.72;

    //! Vertical cylinder of radius r from z0 to z1 around (cx, cy), with a top cap.
    bool hitCylinder( const Eigen::Vector3d &o, const Eigen::Vector3d &d, double cx, double cy, double r, double z0, double z1,
                      double tMax, double &t, Eigen::Vector3d &normal )
    {
      bool found = false;
      const double ox = o.x() - cx, oy = o.y() - cy;
      const double a = d.x() * d.x() + d.y() * d.y();
      if ( a > 1e-14 )
      {
        const double b = ox * d.x() + oy * d.y();
        const double c = ox * ox + oy * oy - r * r;
        const double disc = b * b - a * c;
        if ( disc >= 0.0 )
        {
          const double sq = std::sqrt( disc );
          for ( double root : { ( -b - sq ) / a, ( -b + sq ) / a } )
          {
            if ( root > 1e-9 && root < tMax )
            {
              const double z = o.z() + d.z() * root;
              if ( z >= z0 && z <= z1 )
              {
                t = root;
                tMax = root;
                normal = Eigen::Vector3d( ( ox + d.x() * root ) / r, ( oy + d.y() * root ) / r, 0.0 );
                found = true;
                break;
              }
            }
          }
        }
      }
      if ( std::abs( d.z() ) > 1e-14 )
      {
        const double root = ( z1 - o.z() ) / d.z();
        if ( root > 1e-9 && root < tMax )
        {
          const double px = ox + d.x() * root, py = oy + d.y() * root;
          if ( px * px + py * py <= r * r )
          {
            t = root;
            normal = Eigen::Vector3d::UnitZ();
            found = true;
          }
        }
      }
      return found;
    }

    bool hitSphere( const Eigen::Vector3d &o, const Eigen::Vector3d &d, const Eigen::Vector3d &c, double r, double tMax, double &t, Eigen::Vector3d &normal )
    {
      const Eigen::Vector3d oc = o - c;
      const double b = oc.dot( d ), cc = oc.squaredNorm() - r * r;
      const double disc = b * b - cc;
      if ( disc < 0.0 )
        return false;
      const double sq = std::sqrt( disc );
      double root = -b - sq;
      if ( root <= 1e-9 )
        root = -b + sq;
      if ( root <= 1e-9 || root >= tMax )
        return false;
      t = root;
      normal = ( oc + d * root ) / r;
      return true;
    }

    //! Box of half extents h around centre c, rotated by heading about Z.
    bool hitBox( const Eigen::Vector3d &o, const Eigen::Vector3d &d, const Eigen::Vector3d &c, double heading, const Eigen::Vector3d &h,
                 double tMax, double &t, Eigen::Vector3d &normal )
    {
      const double ch = std::cos( heading ), sh = std::sin( heading );
      const Eigen::Vector3d rel = o - c;
      const Eigen::Vector3d lo( ch * rel.x() + sh * rel.y(), -sh * rel.x() + ch * rel.y(), rel.z() );
      const Eigen::Vector3d ld( ch * d.x() + sh * d.y(), -sh * d.x() + ch * d.y(), d.z() );
      double tNear = 1e-9, tFar = tMax;
      int axis = -1;
      double sign = 1.0;
      for ( int k = 0; k < 3; ++k )
      {
        if ( std::abs( ld[k] ) < 1e-14 )
        {
          if ( std::abs( lo[k] ) > h[k] )
            return false;
          continue;
        }
        double t0 = ( -h[k] - lo[k] ) / ld[k], t1 = ( h[k] - lo[k] ) / ld[k];
        double s = -1.0;
        if ( t0 > t1 )
        {
          std::swap( t0, t1 );
          s = 1.0;
        }
        if ( t0 > tNear )
        {
          tNear = t0;
          axis = k;
          sign = s;
        }
        tFar = std::min( tFar, t1 );
        if ( tNear > tFar )
          return false;
      }
      if ( axis < 0 )
        return false; // starts inside
      t = tNear;
      Eigen::Vector3d ln = Eigen::Vector3d::Zero();
      ln[axis] = sign;
      normal = Eigen::Vector3d( ch * ln.x() - sh * ln.y(), sh * ln.x() + ch * ln.y(), ln.z() );
      return true;
    }

    ShadowShape capsule( const Eigen::Vector2d &a, const Eigen::Vector2d &b, double r )
    {
      ShadowShape s;
      s.type = ShadowShape::Type::Capsule;
      s.a = a;
      s.b = b;
      s.radius = r;
      s.boxMin = a.cwiseMin( b ) - Eigen::Vector2d::Constant( r );
      s.boxMax = a.cwiseMax( b ) + Eigen::Vector2d::Constant( r );
      return s;
    }

    ShadowShape ellipse( const Eigen::Vector2d &centre, double across, double along, const Eigen::Vector2d &axis )
    {
      ShadowShape s;
      s.type = ShadowShape::Type::Ellipse;
      s.a = centre;
      s.radius = across;
      s.along = along;
      s.axis = axis;
      s.boxMin = centre - Eigen::Vector2d::Constant( std::max( across, along ) );
      s.boxMax = centre + Eigen::Vector2d::Constant( std::max( across, along ) );
      return s;
    }
  }

  std::string objectKindName( ObjectKind kind )
  {
    switch ( kind )
    {
      case ObjectKind::Pole:
        return "pole";
      case ObjectKind::Sign:
        return "sign";
      case ObjectKind::Hydrant:
        return "hydrant";
      case ObjectKind::Tree:
        return "tree";
      case ObjectKind::Car:
        return "car";
    }
    return "object";
  }

  Eigen::Vector3d SceneObject::truthPoint() const
  {
    if ( kind == ObjectKind::Sign )
      return base + Eigen::Vector3d( kSignOffset * std::cos( headingRad ), kSignOffset * std::sin( headingRad ), kSignCentreHeight );
    return base;
  }

  double SceneObject::heightM() const
  {
    switch ( kind )
    {
      case ObjectKind::Pole:
        return kPoleHeight;
      case ObjectKind::Sign:
        return kSignCentreHeight + kSignRadius;
      case ObjectKind::Hydrant:
        return kHydrantCapHeight;
      case ObjectKind::Tree:
        return kCrownHeight + kCrownRadius;
      case ObjectKind::Car:
        return 2 * kCarHalfHeight;
    }
    return 0.0;
  }

  double SceneObject::footprintRadiusM() const
  {
    switch ( kind )
    {
      case ObjectKind::Pole:
        return kPoleRadius;
      case ObjectKind::Sign:
        return kSignRadius + kSignOffset;
      case ObjectKind::Hydrant:
        return kHydrantRadius;
      case ObjectKind::Tree:
        return kCrownRadius;
      case ObjectKind::Car:
        return std::hypot( kCarHalfLength, kCarHalfWidth );
    }
    return 0.0;
  }

  bool intersectObject( const SceneObject &object, const Eigen::Vector3d &o, const Eigen::Vector3d &d, double tMax, ObjectHit &hit )
  {
    const Eigen::Vector3d &b = object.base;
    double t = tMax;
    Eigen::Vector3d n;
    bool found = false;
    switch ( object.kind )
    {
      case ObjectKind::Pole:
        if ( hitCylinder( o, d, b.x(), b.y(), kPoleRadius, b.z() - 0.5, b.z() + kPoleHeight, tMax, t, n ) )
        {
          found = true;
          hit.albedo = object.colour;
          hit.part = 0;
        }
        break;
      case ObjectKind::Hydrant:
        if ( hitCylinder( o, d, b.x(), b.y(), kHydrantRadius, b.z() - 0.5, b.z() + kHydrantHeight, tMax, t, n ) )
        {
          found = true;
          hit.albedo = object.colour;
          hit.part = 0;
        }
        if ( hitCylinder( o, d, b.x(), b.y(), kHydrantCapRadius, b.z() + kHydrantHeight, b.z() + kHydrantCapHeight, found ? t : tMax, t, n ) )
        {
          found = true;
          hit.albedo = object.colour * 0.8f;
          hit.part = 1;
        }
        break;
      case ObjectKind::Tree:
        if ( hitCylinder( o, d, b.x(), b.y(), kTrunkRadius, b.z() - 0.5, b.z() + kTrunkHeight, tMax, t, n ) )
        {
          found = true;
          hit.albedo = Eigen::Vector3f( 0.35f, 0.25f, 0.15f );
          hit.part = 0;
        }
        if ( hitSphere( o, d, b + Eigen::Vector3d( 0, 0, kCrownHeight ), kCrownRadius, found ? t : tMax, t, n ) )
        {
          found = true;
          hit.albedo = object.colour;
          hit.part = 1;
        }
        break;
      case ObjectKind::Car:
        if ( hitBox( o, d, b + Eigen::Vector3d( 0, 0, kCarHalfHeight ), object.headingRad, Eigen::Vector3d( kCarHalfLength, kCarHalfWidth, kCarHalfHeight ), tMax, t, n ) )
        {
          found = true;
          // windows: the upper part of the sides is dark glass
          const Eigen::Vector3d p = o + d * t;
          const bool glass = n.z() < 0.5 && p.z() > b.z() + 1.05;
          hit.albedo = glass ? Eigen::Vector3f( 0.08f, 0.1f, 0.12f ) : object.colour;
          hit.part = glass ? 1 : 0;
        }
        break;
      case ObjectKind::Sign:
      {
        if ( hitCylinder( o, d, b.x(), b.y(), kSignPostRadius, b.z() - 0.5, b.z() + kSignCentreHeight, tMax, t, n ) )
        {
          found = true;
          hit.albedo = Eigen::Vector3f( 0.55f, 0.55f, 0.55f );
          hit.part = 0;
        }
        const Eigen::Vector3d facing( std::cos( object.headingRad ), std::sin( object.headingRad ), 0.0 );
        const Eigen::Vector3d centre = object.truthPoint();
        const double denom = d.dot( facing );
        if ( std::abs( denom ) > 1e-12 )
        {
          const double root = ( centre - o ).dot( facing ) / denom;
          const double limit = found ? t : tMax;
          if ( root > 1e-9 && root < limit )
          {
            const double r = ( o + d * root - centre ).norm();
            if ( r <= kSignRadius )
            {
              found = true;
              t = root;
              n = denom < 0.0 ? facing : -facing;
              if ( denom < 0.0 ) // the face: red ring, white inside
              {
                hit.albedo = r > 0.75 * kSignRadius ? Eigen::Vector3f( 0.75f, 0.05f, 0.05f ) : Eigen::Vector3f( 0.92f, 0.92f, 0.92f );
                hit.part = r > 0.75 * kSignRadius ? 1 : 2;
              }
              else
              {
                hit.albedo = Eigen::Vector3f( 0.5f, 0.5f, 0.52f );
                hit.part = 3;
              }
            }
          }
        }
        break;
      }
    }
    if ( found )
    {
      hit.t = t;
      hit.normal = n;
    }
    return found;
  }

  bool ShadowShape::contains( const Eigen::Vector2d &p ) const
  {
    switch ( type )
    {
      case Type::Capsule:
      {
        const Eigen::Vector2d ab = b - a;
        const double len2 = ab.squaredNorm();
        const double u = len2 > 0.0 ? std::clamp( ( p - a ).dot( ab ) / len2, 0.0, 1.0 ) : 0.0;
        return ( p - ( a + u * ab ) ).squaredNorm() <= radius * radius;
      }
      case Type::Ellipse:
      {
        const Eigen::Vector2d rel = p - a;
        const double u = rel.dot( axis ) / along, v = ( rel.x() * -axis.y() + rel.y() * axis.x() ) / radius;
        return u * u + v * v <= 1.0;
      }
      case Type::Polygon:
      {
        for ( size_t i = 0; i < polygon.size(); ++i )
        {
          const Eigen::Vector2d &q0 = polygon[i], &q1 = polygon[( i + 1 ) % polygon.size()];
          if ( ( q1.x() - q0.x() ) * ( p.y() - q0.y() ) - ( q1.y() - q0.y() ) * ( p.x() - q0.x() ) < 0.0 )
            return false;
        }
        return true;
      }
    }
    return false;
  }

  std::vector<ShadowShape> objectShadows( const SceneObject &object, const Eigen::Vector3d &towardsSun )
  {
    std::vector<ShadowShape> shapes;
    if ( towardsSun.z() <= 0.05 )
      return shapes;
    const Eigen::Vector2d step = -towardsSun.head<2>() / towardsSun.z(); // ground offset per metre of height
    const Eigen::Vector2d axis = step.norm() > 1e-9 ? step.normalized() : Eigen::Vector2d::UnitX();
    const Eigen::Vector2d foot = object.base.head<2>();
    const double stretch = 1.0 / towardsSun.z(); // along-sun semi-axis of a sphere's shadow over its radius (|towardsSun| = 1)
    switch ( object.kind )
    {
      case ObjectKind::Pole:
        shapes.push_back( capsule( foot, foot + step * kPoleHeight, kPoleRadius ) );
        break;
      case ObjectKind::Hydrant:
        shapes.push_back( capsule( foot, foot + step * kHydrantCapHeight, kHydrantRadius ) );
        break;
      case ObjectKind::Tree:
        shapes.push_back( capsule( foot, foot + step * kTrunkHeight, kTrunkRadius ) );
        shapes.push_back( ellipse( foot + step * kCrownHeight, kCrownRadius, kCrownRadius * stretch, axis ) );
        break;
      case ObjectKind::Sign:
        shapes.push_back( capsule( foot, foot + step * kSignCentreHeight, kSignPostRadius ) );
        shapes.push_back( ellipse( foot + step * kSignCentreHeight, kSignRadius * 0.8, kSignRadius * 0.8 * stretch, axis ) );
        break;
      case ObjectKind::Car:
      {
        const double ch = std::cos( object.headingRad ), sh = std::sin( object.headingRad );
        std::vector<Eigen::Vector2d> points;
        for ( double sx : { -1.0, 1.0 } )
          for ( double sy : { -1.0, 1.0 } )
            for ( double z : { 0.0, 2 * kCarHalfHeight } )
            {
              const Eigen::Vector2d local( sx * kCarHalfLength, sy * kCarHalfWidth );
              points.push_back( foot + Eigen::Vector2d( ch * local.x() - sh * local.y(), sh * local.x() + ch * local.y() ) + step * z );
            }
        // convex hull (monotone chain), counter-clockwise
        std::sort( points.begin(), points.end(), []( const Eigen::Vector2d &p, const Eigen::Vector2d &q )
        { return p.x() < q.x() || ( p.x() == q.x() && p.y() < q.y() ); } );
        std::vector<Eigen::Vector2d> hull( 2 * points.size() );
        size_t k = 0;
        const auto cross = []( const Eigen::Vector2d &o, const Eigen::Vector2d &a, const Eigen::Vector2d &b )
        { return ( a.x() - o.x() ) * ( b.y() - o.y() ) - ( a.y() - o.y() ) * ( b.x() - o.x() ); };
        for ( size_t i = 0; i < points.size(); ++i )
        {
          while ( k >= 2 && cross( hull[k - 2], hull[k - 1], points[i] ) <= 0 )
            --k;
          hull[k++] = points[i];
        }
        for ( size_t i = points.size() - 1, lower = k + 1; i-- > 0; )
        {
          while ( k >= lower && cross( hull[k - 2], hull[k - 1], points[i] ) <= 0 )
            --k;
          hull[k++] = points[i];
        }
        hull.resize( k - 1 );
        ShadowShape s;
        s.type = ShadowShape::Type::Polygon;
        s.polygon = hull;
        s.boxMin = s.boxMax = hull.front();
        for ( const Eigen::Vector2d &p : hull )
        {
          s.boxMin = s.boxMin.cwiseMin( p );
          s.boxMax = s.boxMax.cwiseMax( p );
        }
        shapes.push_back( s );
        break;
      }
    }
    return shapes;
  }

} // namespace geostation

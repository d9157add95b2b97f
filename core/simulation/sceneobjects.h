/***************************************************************************
  sceneobjects.h - 3-D objects, ground marks and shadows of the simulator
  -------------------------------------------------------------------------
  Objects stand on the terrain at `base` (block CRS, the foot of the object's
  axis on the ground). Their truth point is what an operator measures:
  the foot of a pole, hydrant or tree, the centre of a sign plate.
  Ground marks (manhole lids, signalised control targets) are painted on
  the terrain. Shadows are the objects' outlines projected along the sun
  onto the ground plane at each object's foot.
 ***************************************************************************/
#ifndef GEOSTATION_SIMULATION_SCENEOBJECTS_H
#define GEOSTATION_SIMULATION_SCENEOBJECTS_H

#include <string>
#include <vector>

#include <Eigen/Core>

namespace geostation
{

  enum class ObjectKind
  {
    Pole,
    Sign,
    Hydrant,
    Tree,
    Car,
  };

  //! The name of a kind in the truth GeoPackage: pole, sign, hydrant, tree, car.
  std::string objectKindName( ObjectKind kind );

  struct SceneObject
  {
    std::string id;
    ObjectKind kind = ObjectKind::Pole;
    Eigen::Vector3d base = Eigen::Vector3d::Zero(); //!< foot on the terrain, block CRS
    double headingRad = 0.0;  //!< direction the object faces (sign) or points (car), from +X counter-clockwise
    Eigen::Vector3f colour = Eigen::Vector3f( 0.6f, 0.6f, 0.6f ); //!< albedo, 0..1

    //! The point an operator measures (see the file comment).
    Eigen::Vector3d truthPoint() const;
    //! Height of the top above the base, metres.
    double heightM() const;
    //! Horizontal radius of a circle around the base containing the object, metres.
    double footprintRadiusM() const;
  };

  //! What a ray hit on an object.
  struct ObjectHit
  {
    double t = 0.0;
    Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
    Eigen::Vector3f albedo = Eigen::Vector3f::Zero();
    int part = 0; //!< distinguishes surfaces of one object for anti-aliasing
  };

  //! The first hit on `object` for t in (0, tMax); `direction` is a unit vector.
  bool intersectObject( const SceneObject &object, const Eigen::Vector3d &origin, const Eigen::Vector3d &direction, double tMax, ObjectHit &hit );

  enum class GroundMarkKind
  {
    Manhole,
    Target, //!< signalised control point: white disc on a black square
  };

  struct GroundMark
  {
    std::string id;
    GroundMarkKind kind = GroundMarkKind::Manhole;
    Eigen::Vector3d centre = Eigen::Vector3d::Zero(); //!< on the terrain, block CRS
    double radiusM = 0.3;      //!< lid or white disc radius
    double squareHalfM = 0.0;  //!< targets: half side of the black square
    double reachM() const { return kind == GroundMarkKind::Target ? squareHalfM * 1.4143 : radiusM; }
  };

  //! An object's shadow on the ground plane through its foot.
  struct ShadowShape
  {
    enum class Type { Capsule, Ellipse, Polygon };
    Type type = Type::Capsule;
    Eigen::Vector2d a = Eigen::Vector2d::Zero(), b = Eigen::Vector2d::Zero(); //!< capsule axis; ellipse centre in a
    double radius = 0.0;          //!< capsule radius; ellipse semi-axis across the sun
    double along = 0.0;           //!< ellipse semi-axis along the sun
    Eigen::Vector2d axis = Eigen::Vector2d::UnitX(); //!< ellipse: unit direction along the sun
    std::vector<Eigen::Vector2d> polygon; //!< convex, counter-clockwise
    Eigen::Vector2d boxMin, boxMax;

    bool contains( const Eigen::Vector2d &p ) const;
  };

  //! The shadows of an object for a sun in direction `towardsSun` (unit, z > 0).
  std::vector<ShadowShape> objectShadows( const SceneObject &object, const Eigen::Vector3d &towardsSun );

} // namespace geostation

#endif // GEOSTATION_SIMULATION_SCENEOBJECTS_H

/***************************************************************************
  colmapconversion.cpp - COLMAP cameras and poses to GeoStation's and back
 ***************************************************************************/
#include "io/colmapconversion.h"

#include <cmath>
#include <limits>
#include <stdexcept>

#include <Eigen/Geometry>

#include "geometry/rotation.h"

namespace geostation
{
  namespace
  {
    const Eigen::Matrix3d kFlipYZ = Eigen::Vector3d( 1.0, -1.0, -1.0 ).asDiagonal();

    using Matrix3ld = Eigen::Matrix<long double, 3, 3>;
    using Vector3ld = Eigen::Matrix<long double, 3, 1>;

    /**
     * camFromWorld of a quaternion in extended precision. Export and import
     * both take the rotation from the quaternion as written, so at projected
     * coordinates (10^6 m) centre -> t -> centre loses only t's rounding.
     */
    Matrix3ld camFromWorldOf( const Eigen::Vector4d &qvec )
    {
      const Eigen::Quaternion<long double> q( qvec[0], qvec[1], qvec[2], qvec[3] );
      return q.normalized().toRotationMatrix();
    }

    std::string describe( const ColmapCamera &c )
    {
      return "COLMAP camera " + std::to_string( c.id ) + " (" + c.model + ")";
    }
  }

  CameraFromColmap cameraFromColmap( const ColmapCamera &colmapCamera, const std::string &cameraId )
  {
    const std::vector<double> &p = colmapCamera.params;
    using Status = CameraConversionStatus;
    auto refuse = [&]( Status status, const std::string &why ) {
      CameraFromColmap refused;
      refused.status = status;
      refused.message = describe( colmapCamera ) + " " + why;
      return refused;
    };
    if ( colmapCameraModelParameterCount( colmapCamera.model ) != static_cast<int>( p.size() ) )
      return refuse( Status::Malformed, "has " + std::to_string( p.size() ) + " parameters, not the model's " + std::to_string( colmapCameraModelParameterCount( colmapCamera.model ) ) );
    for ( double v : p )
      if ( !std::isfinite( v ) )
        return refuse( Status::Malformed, "has a parameter that is not a number" );
    if ( colmapCamera.width == 0 || colmapCamera.height == 0 || colmapCamera.width > 1000000 || colmapCamera.height > 1000000 )
      return refuse( Status::Malformed, "has the impossible size " + std::to_string( colmapCamera.width ) + " x " + std::to_string( colmapCamera.height ) + " pixels" );

    Camera camera;
    camera.id = cameraId;
    camera.width = static_cast<int>( colmapCamera.width );
    camera.height = static_cast<int>( colmapCamera.height );
    double fx = 0.0, fy = 0.0;
    std::array<double, kDistortionCoefficientCount> k { 0, 0, 0, 0, 0 }; // k1, k2, p1, p2, k3
    const std::string &m = colmapCamera.model;
    if ( m == "SIMPLE_PINHOLE" || m == "SIMPLE_RADIAL" || m == "RADIAL" )
    {
      fx = fy = p[0];
      camera.cx = p[1];
      camera.cy = p[2];
      if ( m != "SIMPLE_PINHOLE" )
        k[0] = p[3];
      if ( m == "RADIAL" )
        k[1] = p[4];
    }
    else if ( m == "PINHOLE" || m == "OPENCV" || m == "FULL_OPENCV" )
    {
      fx = p[0];
      fy = p[1];
      camera.cx = p[2];
      camera.cy = p[3];
      if ( m != "PINHOLE" )
        k = { p[4], p[5], p[6], p[7], m == "FULL_OPENCV" ? p[8] : 0.0 };
      if ( m == "FULL_OPENCV" && ( p[9] != 0.0 || p[10] != 0.0 || p[11] != 0.0 ) )
        return refuse( Status::NotRepresentable, "has the rational distortion terms k4, k5, k6 (" + std::to_string( p[9] ) + ", " + std::to_string( p[10] ) + ", " + std::to_string( p[11] )
                       + "), which GeoStation's lens models cannot represent exactly" );
    }
    else
      return refuse( Status::NotRepresentable, "uses a lens model GeoStation cannot represent exactly (supported: SIMPLE_PINHOLE, PINHOLE, SIMPLE_RADIAL, RADIAL, OPENCV, FULL_OPENCV without k4-k6)" );
    if ( !( fx > 0.0 ) || !( fy > 0.0 ) )
      return refuse( Status::Malformed, "has a focal length that is not positive" );
    camera.f = fx;
    camera.aspect = fy / fx;
    const bool anyDistortion = k[0] != 0.0 || k[1] != 0.0 || k[2] != 0.0 || k[3] != 0.0 || k[4] != 0.0;
    const bool modelHasDistortion = m != "SIMPLE_PINHOLE" && m != "PINHOLE";
    camera.distortion.model = modelHasDistortion || anyDistortion ? DistortionModel::OpenCV : DistortionModel::None;
    camera.distortion.coeffs = k;
    CameraFromColmap converted;
    converted.camera = camera;
    return converted;
  }

  CameraToColmap colmapCameraFromCamera( const Camera &camera, std::uint32_t colmapId )
  {
    CameraToColmap out;
    ColmapCamera &c = out.camera;
    c.id = colmapId;
    c.width = static_cast<std::uint64_t>( camera.width );
    c.height = static_cast<std::uint64_t>( camera.height );
    const Distortion &d = camera.distortion;
    switch ( d.model )
    {
      case DistortionModel::None:
        if ( camera.aspect == 1.0 )
        {
          c.model = "SIMPLE_PINHOLE";
          c.params = { camera.f, camera.cx, camera.cy };
        }
        else
        {
          c.model = "PINHOLE";
          c.params = { camera.fx(), camera.fy(), camera.cx, camera.cy };
        }
        return out;
      case DistortionModel::OpenCV:
        if ( d.k3() == 0.0 )
        {
          c.model = "OPENCV";
          c.params = { camera.fx(), camera.fy(), camera.cx, camera.cy, d.k1(), d.k2(), d.p1(), d.p2() };
        }
        else
        {
          c.model = "FULL_OPENCV";
          c.params = { camera.fx(), camera.fy(), camera.cx, camera.cy, d.k1(), d.k2(), d.p1(), d.p2(), d.k3(), 0.0, 0.0, 0.0 };
        }
        return out;
      case DistortionModel::BrownPhoto:
        break;
    }
    out.status = CameraConversionStatus::NotRepresentable;
    out.message = "camera \"" + camera.id + "\" uses the lens model brown_photo (a correction of measured photo coordinates), which no COLMAP camera model represents exactly";
    return out;
  }

  ExteriorOrientation exteriorFromColmapPose( const Eigen::Vector4d &qvec, const Eigen::Vector3d &tvec )
  {
    if ( !qvec.allFinite() || !tvec.allFinite() || !( qvec.norm() > 1e-12 ) )
      throw std::invalid_argument( "the pose's quaternion or translation is zero or not a number" );
    const Matrix3ld camFromWorldLd = camFromWorldOf( qvec );
    const Eigen::Matrix3d camFromWorld = camFromWorldLd.cast<double>();
    return ExteriorOrientation::fromCentreAndRotation( ( -( camFromWorldLd.transpose() * tvec.cast<long double>() ) ).cast<double>(), camFromWorld.transpose() * kFlipYZ );
  }

  void colmapPoseFromExterior( const ExteriorOrientation &exterior, Eigen::Vector4d *qvec, Eigen::Vector3d *tvec )
  {
    const Eigen::Matrix3d camFromWorld = kFlipYZ * exterior.worldFromCamera().transpose();
    Eigen::Quaterniond q( camFromWorld );
    q.normalize();
    if ( q.w() < 0.0 )
      q.coeffs() = -q.coeffs();
    *qvec = Eigen::Vector4d( q.w(), q.x(), q.y(), q.z() );
    const Vector3ld centre = exterior.projectionCentre.cast<long double>();
    *tvec = ( -( camFromWorldOf( *qvec ) * centre ) ).cast<double>();
  }

} // namespace geostation

/***************************************************************************
  colmapmodel.h - COLMAP sparse models, text and binary, read and written
  -------------------------------------------------------------------------
  A COLMAP model folder holds cameras, images and points3D, either as
  cameras.txt / images.txt / points3D.txt or as the same names with .bin,
  and from COLMAP 3.12 on also rigs and frames (colmaprigs.h).
  This is that model as COLMAP stores it, without any conversion: COLMAP's
  camera models with their parameter arrays, world-to-camera quaternions
  (w, x, y, z) and translations, 2-D points per image and 3-D points with
  their tracks. Conversion to a GeoStation block is in colmapimport.h.

  Layouts follow COLMAP's own readers and writers (src/base/reconstruction.cc
  of COLMAP 3.x): binary files are little-endian with
    cameras.bin:  u64 n; n x { u32 id, i32 model, u64 width, u64 height, f64 params[] }
    images.bin:   u64 n; n x { u32 id, f64 qw qx qy qz, f64 tx ty tz, u32 camera,
                               name '\0', u64 m, m x { f64 x, f64 y, u64 point3D } }
    points3D.bin: u64 n; n x { u64 id, f64 x y z, u8 r g b, f64 error,
                               u64 t, t x { u32 image, u32 point2D index } }
  A 2-D point without a 3-D point has point3D id -1 (all bits set in binary).
 ***************************************************************************/
#ifndef GEOSTATION_IO_COLMAPMODEL_H
#define GEOSTATION_IO_COLMAPMODEL_H

#include <array>
#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "io/colmaprigs.h"

namespace geostation
{

  //! A COLMAP model that cannot be read: names the file and what is wrong.
  class ColmapFormatError : public std::runtime_error
  {
    public:
      explicit ColmapFormatError( const std::string &message )
        : std::runtime_error( message ) {}
  };

  struct ColmapCamera
  {
    std::uint32_t id = 0;
    std::string model;            //!< COLMAP's name, e.g. "OPENCV"
    std::uint64_t width = 0;
    std::uint64_t height = 0;
    std::vector<double> params;   //!< in COLMAP's order for the model
  };

  struct ColmapPoint2D
  {
    Eigen::Vector2d pixel = Eigen::Vector2d::Zero(); //!< COLMAP pixels: top-left corner (0, 0), first centre (0.5, 0.5)
    std::int64_t point3DId = -1;                      //!< -1: no 3-D point
  };

  struct ColmapImage
  {
    std::uint32_t id = 0;
    Eigen::Vector4d qvec { 1, 0, 0, 0 }; //!< camFromWorld rotation as a quaternion (w, x, y, z)
    Eigen::Vector3d tvec = Eigen::Vector3d::Zero(); //!< camFromWorld translation
    std::uint32_t cameraId = 0;
    std::string name;                    //!< path relative to COLMAP's image folder
    std::vector<ColmapPoint2D> points2D;
  };

  struct ColmapTrackElement
  {
    std::uint32_t imageId = 0;
    std::uint32_t point2DIndex = 0;
  };

  struct ColmapPoint3D
  {
    std::uint64_t id = 0;
    Eigen::Vector3d xyz = Eigen::Vector3d::Zero();
    std::array<std::uint8_t, 3> rgb { 0, 0, 0 };
    double error = -1.0;                 //!< mean reprojection error, pixels (-1: unknown)
    std::vector<ColmapTrackElement> track;
  };

  /**
   * The number of parameters of a COLMAP camera model, or -1 for a name
   * COLMAP does not have.
   */
  int colmapCameraModelParameterCount( const std::string &modelName );

  //! COLMAP's numeric model id of a model name, or -1.
  int colmapCameraModelId( const std::string &modelName );

  //! COLMAP's model name of a numeric id, or an empty string.
  std::string colmapCameraModelName( int modelId );

  class ColmapModel
  {
    public:
      std::vector<ColmapCamera> cameras;
      std::vector<ColmapImage> images;
      std::vector<ColmapPoint3D> points3D;
      std::vector<ColmapRig> rigs;     //!< empty for a model of a COLMAP before 3.12
      std::vector<ColmapFrame> frames; //!< empty for a model of a COLMAP before 3.12

      /**
       * Reads a model folder, binary files preferred when both kinds exist.
       * `path` may be the folder or any of its cameras/images/points3D files.
       * points3D is optional (a model of posed images only), and so are
       * rigs and frames (models of COLMAP before 3.12). Throws
       * ColmapFormatError naming the file and the record at fault.
       */
      static ColmapModel read( const std::filesystem::path &path );

      //! The model folder a path names (the folder itself or a file's folder), and whether it is binary.
      static std::filesystem::path modelFolder( const std::filesystem::path &path, bool *binary = nullptr );

      //! True when `path` is (or is in) a folder holding a COLMAP model.
      static bool isModel( const std::filesystem::path &path );

      /**
       * Writes cameras.txt, images.txt and points3D.txt (full precision),
       * and rigs.txt and frames.txt when the model has rigs or frames (a
       * rigs or frames file already in the folder is removed when it has
       * none). The folder is created if needed. Throws std::runtime_error.
       */
      void writeText( const std::filesystem::path &folder ) const;

      //! Writes the .bin files in COLMAP's binary layout, as writeText() the text files. Throws std::runtime_error.
      void writeBinary( const std::filesystem::path &folder ) const;

      const ColmapCamera *findCamera( std::uint32_t id ) const;

    private:
      void writeRigsAndFrames( const std::filesystem::path &folder, bool binary ) const;
  };

} // namespace geostation

#endif // GEOSTATION_IO_COLMAPMODEL_H

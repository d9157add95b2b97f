/***************************************************************************
  colmaprigs.h - the rigs and frames of a COLMAP model (COLMAP 3.12 and on)
  -------------------------------------------------------------------------
  From COLMAP 3.12 a sparse model also holds rigs and frames: a rig is a set
  of sensors (cameras, IMUs) fixed to each other, one of them the reference,
  the others with their pose in the rig where it is known; a frame is one
  instant of a rig - its pose in the world and the data (for a camera: the
  image) each of its sensors took then. A mobile-mapping van's cameras
  fired together are one frame: a GeoStation exposure station. cameras,
  images and points3D keep their old layout, so a model without these
  files is an older COLMAP's, one rig per camera and one frame per image.

  Layouts (COLMAP's src/colmap/scene/reconstruction_io_binary.cc and
  _text.cc), binary little-endian:
    rigs.bin:   u64 n; n x { u32 rig, u32 sensors, [i32 type, u32 id of the
                reference sensor if sensors > 0], (sensors - 1) x { i32 type,
                u32 id, u8 has_pose, [f64 qw qx qy qz tx ty tz if has_pose] } }
    frames.bin: u64 n; n x { u32 frame, u32 rig, f64 qw qx qy qz tx ty tz
                (rig from world), u32 m, m x { i32 type, u32 sensor, u64 data } }
  Sensor types: 0 camera, 1 IMU (text: CAMERA, IMU). For a camera the data
  id is the image id.
 ***************************************************************************/
#ifndef GEOSTATION_IO_COLMAPRIGS_H
#define GEOSTATION_IO_COLMAPRIGS_H

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace geostation
{

  //! A sensor of a COLMAP rig: a camera (its camera id) or an IMU.
  struct ColmapSensor
  {
    enum class Type : std::int32_t
    {
      Camera = 0,
      Imu = 1,
    };
    Type type = Type::Camera;
    std::uint32_t id = 0;

    bool operator==( const ColmapSensor &other ) const { return type == other.type && id == other.id; }
  };

  //! COLMAP's name of a sensor type: "CAMERA" or "IMU".
  std::string colmapSensorTypeName( ColmapSensor::Type type );

  //! A pose as COLMAP stores it: rotation quaternion (w, x, y, z) and translation of "to from from".
  struct ColmapPose
  {
    Eigen::Vector4d qvec { 1, 0, 0, 0 };
    Eigen::Vector3d tvec = Eigen::Vector3d::Zero();
  };

  struct ColmapRigSensor
  {
    ColmapSensor sensor;
    std::optional<ColmapPose> sensorFromRig; //!< unknown until calibrated
  };

  struct ColmapRig
  {
    std::uint32_t id = 0;
    std::optional<ColmapSensor> reference;   //!< nothing for a rig without sensors
    std::vector<ColmapRigSensor> others;     //!< the sensors besides the reference
  };

  struct ColmapFrameData
  {
    ColmapSensor sensor;
    std::uint64_t dataId = 0; //!< for a camera: the image id
  };

  struct ColmapFrame
  {
    std::uint32_t id = 0;
    std::uint32_t rigId = 0;
    ColmapPose rigFromWorld;
    std::vector<ColmapFrameData> data;
  };

  /**
   * Reads rigs.bin / frames.bin (or the .txt) of a model folder. Throws
   * ColmapFormatError naming the file and the record at fault.
   */
  std::vector<ColmapRig> readColmapRigs( const std::filesystem::path &file, bool binary );
  std::vector<ColmapFrame> readColmapFrames( const std::filesystem::path &file, bool binary );

  //! Writes rigs.bin / frames.bin (or the .txt, full precision). Throws std::runtime_error.
  void writeColmapRigs( const std::vector<ColmapRig> &rigs, const std::filesystem::path &file, bool binary );
  void writeColmapFrames( const std::vector<ColmapFrame> &frames, const std::filesystem::path &file, bool binary );

} // namespace geostation

#endif // GEOSTATION_IO_COLMAPRIGS_H

/***************************************************************************
  colmaprigs.cpp - the rigs and frames of a COLMAP model
 ***************************************************************************/
#include "io/colmaprigs.h"

#include "io/colmapmodel.h"
#include "io/internal/colmapfiles.h"

namespace fs = std::filesystem;

namespace geostation
{
  using namespace colmapfiles;

  namespace
  {
    ColmapSensor::Type sensorType( std::int32_t value, const std::string &where )
    {
      if ( value != 0 && value != 1 )
        throw ColmapFormatError( where + ": the sensor type " + std::to_string( value ) + " (COLMAP knows 0, a camera, and 1, an IMU)" );
      return static_cast<ColmapSensor::Type>( value );
    }

    ColmapSensor::Type sensorType( const std::string &name, const TextLines &lines )
    {
      if ( name == "CAMERA" )
        return ColmapSensor::Type::Camera;
      if ( name == "IMU" )
        return ColmapSensor::Type::Imu;
      lines.fail( "the sensor type '" + name + "' (COLMAP knows CAMERA and IMU)" );
    }

    ColmapPose readPose( BinaryCursor &in, const char *what )
    {
      ColmapPose pose;
      for ( int i = 0; i < 4; ++i )
        pose.qvec[i] = in.read<double>( what );
      for ( int i = 0; i < 3; ++i )
        pose.tvec[i] = in.read<double>( what );
      return pose;
    }

    ColmapPose parsePose( std::istringstream &fields, const TextLines &lines, const char *what )
    {
      ColmapPose pose;
      for ( int i = 0; i < 4; ++i )
        pose.qvec[i] = parseField<double>( fields, lines, what );
      for ( int i = 0; i < 3; ++i )
        pose.tvec[i] = parseField<double>( fields, lines, what );
      return pose;
    }

    void putPose( std::ofstream &out, const ColmapPose &pose )
    {
      for ( int i = 0; i < 4; ++i )
        put<double>( out, pose.qvec[i] );
      for ( int i = 0; i < 3; ++i )
        put<double>( out, pose.tvec[i] );
    }

    void printPose( std::ofstream &out, const ColmapPose &pose )
    {
      out << pose.qvec[0] << ' ' << pose.qvec[1] << ' ' << pose.qvec[2] << ' ' << pose.qvec[3] << ' ' << pose.tvec[0] << ' ' << pose.tvec[1] << ' ' << pose.tvec[2];
    }

    void rejectTrailing( std::istringstream &fields, const TextLines &lines, const std::string &record )
    {
      std::string extra;
      if ( fields >> extra )
        lines.fail( "more than " + record + " holds ('" + extra + "')" );
    }

    std::vector<ColmapRig> readRigsBinary( const fs::path &file )
    {
      BinaryCursor in( file );
      std::vector<ColmapRig> rigs( in.readCount( 8, "rigs" ) );
      for ( ColmapRig &rig : rigs )
      {
        rig.id = in.read<std::uint32_t>( "a rig id" );
        const std::uint32_t sensors = in.read<std::uint32_t>( "a rig's sensor count" );
        const std::string where = "the COLMAP file " + file.string() + ", rig " + std::to_string( rig.id );
        if ( sensors > 0 )
        {
          ColmapSensor reference;
          reference.type = sensorType( in.read<std::int32_t>( "a rig's reference sensor" ), where );
          reference.id = in.read<std::uint32_t>( "a rig's reference sensor" );
          rig.reference = reference;
        }
        for ( std::uint32_t i = 1; i < sensors; ++i )
        {
          ColmapRigSensor s;
          s.sensor.type = sensorType( in.read<std::int32_t>( "a rig's sensor" ), where );
          s.sensor.id = in.read<std::uint32_t>( "a rig's sensor" );
          if ( in.read<std::uint8_t>( "a rig sensor's pose flag" ) )
            s.sensorFromRig = readPose( in, "a rig sensor's pose" );
          rig.others.push_back( s );
        }
      }
      if ( !in.atEnd() )
        throw ColmapFormatError( "the COLMAP file " + file.string() + " has bytes after its last rig (not a COLMAP binary file of this version)" );
      return rigs;
    }

    std::vector<ColmapRig> readRigsText( const fs::path &file )
    {
      TextLines lines( file );
      std::vector<ColmapRig> rigs;
      std::string line;
      while ( lines.nextRecord( line ) )
      {
        std::istringstream f( line );
        ColmapRig rig;
        rig.id = parseField<std::uint32_t>( f, lines, "RIG_ID" );
        const std::uint32_t sensors = parseField<std::uint32_t>( f, lines, "NUM_SENSORS" );
        if ( sensors > 0 )
        {
          ColmapSensor reference;
          reference.type = sensorType( parseField<std::string>( f, lines, "REF_SENSOR_TYPE" ), lines );
          reference.id = parseField<std::uint32_t>( f, lines, "REF_SENSOR_ID" );
          rig.reference = reference;
        }
        for ( std::uint32_t i = 1; i < sensors; ++i )
        {
          ColmapRigSensor s;
          s.sensor.type = sensorType( parseField<std::string>( f, lines, "SENSOR_TYPE" ), lines );
          s.sensor.id = parseField<std::uint32_t>( f, lines, "SENSOR_ID" );
          const int hasPose = parseField<int>( f, lines, "HAS_POSE" );
          if ( hasPose != 0 && hasPose != 1 )
            lines.fail( "HAS_POSE is " + std::to_string( hasPose ) + " (0 or 1)" );
          if ( hasPose )
            s.sensorFromRig = parsePose( f, lines, "QW QX QY QZ TX TY TZ of a sensor in the rig" );
          rig.others.push_back( s );
        }
        rejectTrailing( f, lines, "the " + std::to_string( sensors ) + " sensors of rig " + std::to_string( rig.id ) );
        rigs.push_back( std::move( rig ) );
      }
      return rigs;
    }

    std::vector<ColmapFrame> readFramesBinary( const fs::path &file )
    {
      BinaryCursor in( file );
      std::vector<ColmapFrame> frames( in.readCount( 68, "frames" ) );
      for ( ColmapFrame &frame : frames )
      {
        frame.id = in.read<std::uint32_t>( "a frame id" );
        frame.rigId = in.read<std::uint32_t>( "a frame's rig id" );
        frame.rigFromWorld = readPose( in, "a frame's pose" );
        frame.data.resize( in.readCount<std::uint32_t>( 16, "data ids of a frame" ) );
        const std::string where = "the COLMAP file " + file.string() + ", frame " + std::to_string( frame.id );
        for ( ColmapFrameData &d : frame.data )
        {
          d.sensor.type = sensorType( in.read<std::int32_t>( "a frame's data id" ), where );
          d.sensor.id = in.read<std::uint32_t>( "a frame's data id" );
          d.dataId = in.read<std::uint64_t>( "a frame's data id" );
        }
      }
      if ( !in.atEnd() )
        throw ColmapFormatError( "the COLMAP file " + file.string() + " has bytes after its last frame (not a COLMAP binary file of this version)" );
      return frames;
    }

    std::vector<ColmapFrame> readFramesText( const fs::path &file )
    {
      TextLines lines( file );
      std::vector<ColmapFrame> frames;
      std::string line;
      while ( lines.nextRecord( line ) )
      {
        std::istringstream f( line );
        ColmapFrame frame;
        frame.id = parseField<std::uint32_t>( f, lines, "FRAME_ID" );
        frame.rigId = parseField<std::uint32_t>( f, lines, "RIG_ID" );
        frame.rigFromWorld = parsePose( f, lines, "RIG_FROM_WORLD as QW QX QY QZ TX TY TZ" );
        const std::uint32_t n = parseField<std::uint32_t>( f, lines, "NUM_DATA_IDS" );
        for ( std::uint32_t i = 0; i < n; ++i )
        {
          ColmapFrameData d;
          d.sensor.type = sensorType( parseField<std::string>( f, lines, "SENSOR_TYPE" ), lines );
          d.sensor.id = parseField<std::uint32_t>( f, lines, "SENSOR_ID" );
          d.dataId = parseField<std::uint64_t>( f, lines, "DATA_ID" );
          frame.data.push_back( d );
        }
        rejectTrailing( f, lines, "the " + std::to_string( n ) + " data ids of frame " + std::to_string( frame.id ) );
        frames.push_back( std::move( frame ) );
      }
      return frames;
    }
  } // namespace

  std::string colmapSensorTypeName( ColmapSensor::Type type )
  {
    return type == ColmapSensor::Type::Imu ? "IMU" : "CAMERA";
  }

  std::vector<ColmapRig> readColmapRigs( const fs::path &file, bool binary )
  {
    return binary ? readRigsBinary( file ) : readRigsText( file );
  }

  std::vector<ColmapFrame> readColmapFrames( const fs::path &file, bool binary )
  {
    return binary ? readFramesBinary( file ) : readFramesText( file );
  }

  void writeColmapRigs( const std::vector<ColmapRig> &rigs, const fs::path &file, bool binary )
  {
    std::ofstream out = openForWriting( file, binary );
    if ( binary )
      put<std::uint64_t>( out, rigs.size() );
    else
      out << "# Rig calib list with one line of data per calib:\n#   RIG_ID, NUM_SENSORS, REF_SENSOR_TYPE, REF_SENSOR_ID, SENSORS[] as (SENSOR_TYPE, SENSOR_ID, HAS_POSE, [QW, QX, QY, QZ, TX, TY, TZ])\n"
          << "# Number of rigs: " << rigs.size() << '\n';
    for ( const ColmapRig &rig : rigs )
    {
      if ( !rig.reference && !rig.others.empty() )
        throw std::runtime_error( "rig " + std::to_string( rig.id ) + " has sensors but no reference sensor, which COLMAP cannot store" );
      const std::uint32_t sensors = rig.reference ? static_cast<std::uint32_t>( rig.others.size() + 1 ) : 0;
      if ( binary )
      {
        put<std::uint32_t>( out, rig.id );
        put<std::uint32_t>( out, sensors );
        if ( rig.reference )
        {
          put<std::int32_t>( out, static_cast<std::int32_t>( rig.reference->type ) );
          put<std::uint32_t>( out, rig.reference->id );
        }
        for ( const ColmapRigSensor &s : rig.others )
        {
          put<std::int32_t>( out, static_cast<std::int32_t>( s.sensor.type ) );
          put<std::uint32_t>( out, s.sensor.id );
          put<std::uint8_t>( out, s.sensorFromRig ? 1 : 0 );
          if ( s.sensorFromRig )
            putPose( out, *s.sensorFromRig );
        }
        continue;
      }
      out << rig.id << ' ' << sensors;
      if ( rig.reference )
        out << ' ' << colmapSensorTypeName( rig.reference->type ) << ' ' << rig.reference->id;
      for ( const ColmapRigSensor &s : rig.others )
      {
        out << ' ' << colmapSensorTypeName( s.sensor.type ) << ' ' << s.sensor.id << ' ' << ( s.sensorFromRig ? 1 : 0 );
        if ( s.sensorFromRig )
        {
          out << ' ';
          printPose( out, *s.sensorFromRig );
        }
      }
      out << '\n';
    }
    finish( out, file );
  }

  void writeColmapFrames( const std::vector<ColmapFrame> &frames, const fs::path &file, bool binary )
  {
    std::ofstream out = openForWriting( file, binary );
    if ( binary )
      put<std::uint64_t>( out, frames.size() );
    else
      out << "# Frame list with one line of data per frame:\n#   FRAME_ID, RIG_ID, RIG_FROM_WORLD[QW, QX, QY, QZ, TX, TY, TZ], NUM_DATA_IDS, DATA_IDS[] as (SENSOR_TYPE, SENSOR_ID, DATA_ID)\n"
          << "# Number of frames: " << frames.size() << '\n';
    for ( const ColmapFrame &frame : frames )
    {
      if ( binary )
      {
        put<std::uint32_t>( out, frame.id );
        put<std::uint32_t>( out, frame.rigId );
        putPose( out, frame.rigFromWorld );
        put<std::uint32_t>( out, static_cast<std::uint32_t>( frame.data.size() ) );
        for ( const ColmapFrameData &d : frame.data )
        {
          put<std::int32_t>( out, static_cast<std::int32_t>( d.sensor.type ) );
          put<std::uint32_t>( out, d.sensor.id );
          put<std::uint64_t>( out, d.dataId );
        }
        continue;
      }
      out << frame.id << ' ' << frame.rigId << ' ';
      printPose( out, frame.rigFromWorld );
      out << ' ' << frame.data.size();
      for ( const ColmapFrameData &d : frame.data )
        out << ' ' << colmapSensorTypeName( d.sensor.type ) << ' ' << d.sensor.id << ' ' << d.dataId;
      out << '\n';
    }
    finish( out, file );
  }

} // namespace geostation

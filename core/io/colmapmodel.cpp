/***************************************************************************
  colmapmodel.cpp - COLMAP sparse models, text and binary
 ***************************************************************************/
#include "io/colmapmodel.h"
#include "io/internal/colmapfiles.h"

#include <cmath>
#include <cstring>
#include <fstream>
#include <iomanip>
#include <limits>
#include <map>
#include <sstream>
#include <type_traits>

namespace fs = std::filesystem;

namespace geostation
{
  using namespace colmapfiles;

  namespace
  {
    struct ModelInfo
    {
      const char *name;
      int id;
      int parameterCount;
    };

    // COLMAP's camera models (src/base/camera_models.h), ids as COLMAP numbers them
    const ModelInfo kModels[] = {
      { "SIMPLE_PINHOLE", 0, 3 },
      { "PINHOLE", 1, 4 },
      { "SIMPLE_RADIAL", 2, 4 },
      { "RADIAL", 3, 5 },
      { "OPENCV", 4, 8 },
      { "OPENCV_FISHEYE", 5, 8 },
      { "FULL_OPENCV", 6, 12 },
      { "FOV", 7, 5 },
      { "SIMPLE_RADIAL_FISHEYE", 8, 4 },
      { "RADIAL_FISHEYE", 9, 5 },
      { "THIN_PRISM_FISHEYE", 10, 12 },
    };

    const ModelInfo *modelByName( const std::string &name )
    {
      for ( const ModelInfo &m : kModels )
        if ( name == m.name )
          return &m;
      return nullptr;
    }

    std::vector<ColmapCamera> readCamerasBinary( const fs::path &file )
    {
      BinaryCursor in( file );
      std::vector<ColmapCamera> cameras( in.readCount( 24, "cameras" ) );
      for ( ColmapCamera &c : cameras )
      {
        c.id = in.read<std::uint32_t>( "a camera id" );
        const int modelId = in.read<std::int32_t>( "a camera model" );
        c.model = colmapCameraModelName( modelId );
        if ( c.model.empty() )
          throw ColmapFormatError( "the COLMAP file " + file.string() + ": camera " + std::to_string( c.id ) + " has the unknown model number " + std::to_string( modelId ) );
        c.width = in.read<std::uint64_t>( "a camera width" );
        c.height = in.read<std::uint64_t>( "a camera height" );
        c.params.resize( colmapCameraModelParameterCount( c.model ) );
        for ( double &p : c.params )
          p = in.read<double>( "camera parameters" );
      }
      if ( !in.atEnd() )
        throw ColmapFormatError( "the COLMAP file " + file.string() + " has bytes after its last camera (not a COLMAP binary file of this version)" );
      return cameras;
    }

    std::vector<ColmapImage> readImagesBinary( const fs::path &file )
    {
      BinaryCursor in( file );
      std::vector<ColmapImage> images( in.readCount( 73, "images" ) );
      for ( ColmapImage &im : images )
      {
        im.id = in.read<std::uint32_t>( "an image id" );
        for ( int i = 0; i < 4; ++i )
          im.qvec[i] = in.read<double>( "an image quaternion" );
        for ( int i = 0; i < 3; ++i )
          im.tvec[i] = in.read<double>( "an image translation" );
        im.cameraId = in.read<std::uint32_t>( "an image's camera id" );
        im.name = in.readString( "an image name" );
        if ( im.name.empty() || im.name.find_first_of( "\r\n" ) != std::string::npos )
          throw ColmapFormatError( "the COLMAP file " + file.string() + " has an image name that is empty or holds a line break (image " + std::to_string( im.id ) + ")" );
        im.points2D.resize( in.readCount( 24, "2-D points" ) );
        for ( ColmapPoint2D &p : im.points2D )
        {
          p.pixel.x() = in.read<double>( "a 2-D point" );
          p.pixel.y() = in.read<double>( "a 2-D point" );
          const std::uint64_t id = in.read<std::uint64_t>( "a 2-D point's 3-D id" );
          if ( id != std::numeric_limits<std::uint64_t>::max() && id > static_cast<std::uint64_t>( std::numeric_limits<std::int64_t>::max() ) )
            throw ColmapFormatError( "the COLMAP file " + file.string() + " has a 2-D point of image " + std::to_string( im.id ) + " with the 3-D point id " + std::to_string( id ) + " (more than 2^63, and not the all-bits-set of 'none')" );
          p.point3DId = id == std::numeric_limits<std::uint64_t>::max() ? -1 : static_cast<std::int64_t>( id );
        }
      }
      if ( !in.atEnd() )
        throw ColmapFormatError( "the COLMAP file " + file.string() + " has bytes after its last image (not a COLMAP binary file of this version)" );
      return images;
    }

    std::vector<ColmapPoint3D> readPointsBinary( const fs::path &file )
    {
      BinaryCursor in( file );
      std::vector<ColmapPoint3D> points( in.readCount( 51, "3-D points" ) );
      for ( ColmapPoint3D &p : points )
      {
        p.id = in.read<std::uint64_t>( "a 3-D point id" );
        for ( int i = 0; i < 3; ++i )
          p.xyz[i] = in.read<double>( "a 3-D point" );
        for ( int i = 0; i < 3; ++i )
          p.rgb[i] = in.read<std::uint8_t>( "a 3-D point's colour" );
        p.error = in.read<double>( "a 3-D point's error" );
        p.track.resize( in.readCount( 8, "track elements" ) );
        for ( ColmapTrackElement &t : p.track )
        {
          t.imageId = in.read<std::uint32_t>( "a track element" );
          t.point2DIndex = in.read<std::uint32_t>( "a track element" );
        }
      }
      if ( !in.atEnd() )
        throw ColmapFormatError( "the COLMAP file " + file.string() + " has bytes after its last 3-D point (not a COLMAP binary file of this version)" );
      return points;
    }

    std::vector<ColmapCamera> readCamerasText( const fs::path &file )
    {
      TextLines lines( file );
      std::vector<ColmapCamera> cameras;
      std::string line;
      while ( lines.nextRecord( line ) )
      {
        std::istringstream f( line );
        ColmapCamera c;
        c.id = parseField<std::uint32_t>( f, lines, "CAMERA_ID" );
        c.model = parseField<std::string>( f, lines, "MODEL" );
        const int n = colmapCameraModelParameterCount( c.model );
        if ( n < 0 )
          lines.fail( "unknown camera model '" + c.model + "'" );
        c.width = parseField<std::uint64_t>( f, lines, "WIDTH" );
        c.height = parseField<std::uint64_t>( f, lines, "HEIGHT" );
        for ( int i = 0; i < n; ++i )
          c.params.push_back( parseField<double>( f, lines, ( "the " + std::to_string( n ) + " parameters of " + c.model ).c_str() ) );
        std::string extra;
        if ( f >> extra )
          lines.fail( "more than the " + std::to_string( n ) + " parameters of " + c.model );
        cameras.push_back( std::move( c ) );
      }
      return cameras;
    }

    std::vector<ColmapImage> readImagesText( const fs::path &file )
    {
      TextLines lines( file );
      std::vector<ColmapImage> images;
      std::string line;
      while ( lines.nextRecord( line ) )
      {
        std::istringstream f( line );
        ColmapImage im;
        im.id = parseField<std::uint32_t>( f, lines, "IMAGE_ID" );
        for ( int i = 0; i < 4; ++i )
          im.qvec[i] = parseField<double>( f, lines, "QW QX QY QZ" );
        for ( int i = 0; i < 3; ++i )
          im.tvec[i] = parseField<double>( f, lines, "TX TY TZ" );
        im.cameraId = parseField<std::uint32_t>( f, lines, "CAMERA_ID" );
        f >> std::ws;
        std::getline( f, im.name ); // names may contain spaces
        if ( im.name.empty() )
          lines.fail( "expected NAME" );
        if ( im.name.find_first_of( std::string( "\r\0", 2 ) ) != std::string::npos )
          lines.fail( "an image NAME that holds a carriage return or a NUL character" ); // as the binary reader refuses line breaks
        // the last image's empty line of 2-D points may be missing (an editor dropped it); COLMAP reads it as empty too
        std::string points;
        lines.nextLine( points );
        std::istringstream p( points );
        double x, y;
        while ( p >> x )
        {
          ColmapPoint2D pt;
          if ( !( p >> y >> pt.point3DId ) )
            lines.fail( "expected triples X Y POINT3D_ID" );
          if ( pt.point3DId < -1 )
            lines.fail( "a POINT3D_ID of " + std::to_string( pt.point3DId ) + " (-1 for none, or the id of a 3-D point)" );
          pt.pixel = { x, y };
          im.points2D.push_back( pt );
        }
        if ( !p.eof() )
          lines.fail( "expected triples X Y POINT3D_ID" );
        images.push_back( std::move( im ) );
      }
      return images;
    }

    std::vector<ColmapPoint3D> readPointsText( const fs::path &file )
    {
      TextLines lines( file );
      std::vector<ColmapPoint3D> points;
      std::string line;
      while ( lines.nextRecord( line ) )
      {
        std::istringstream f( line );
        ColmapPoint3D p;
        p.id = parseField<std::uint64_t>( f, lines, "POINT3D_ID" );
        for ( int i = 0; i < 3; ++i )
          p.xyz[i] = parseField<double>( f, lines, "X Y Z" );
        for ( int i = 0; i < 3; ++i )
        {
          const int c = parseField<int>( f, lines, "R G B" );
          if ( c < 0 || c > 255 )
            lines.fail( "a colour outside 0-255" );
          p.rgb[i] = static_cast<std::uint8_t>( c );
        }
        p.error = parseField<double>( f, lines, "ERROR" );
        std::uint32_t imageId;
        while ( f >> imageId )
        {
          ColmapTrackElement t;
          t.imageId = imageId;
          t.point2DIndex = parseField<std::uint32_t>( f, lines, "pairs IMAGE_ID POINT2D_IDX" );
          p.track.push_back( t );
        }
        if ( !f.eof() )
          lines.fail( "expected pairs IMAGE_ID POINT2D_IDX" );
        points.push_back( std::move( p ) );
      }
      return points;
    }

  } // namespace

  int colmapCameraModelParameterCount( const std::string &modelName )
  {
    const ModelInfo *m = modelByName( modelName );
    return m ? m->parameterCount : -1;
  }

  int colmapCameraModelId( const std::string &modelName )
  {
    const ModelInfo *m = modelByName( modelName );
    return m ? m->id : -1;
  }

  std::string colmapCameraModelName( int modelId )
  {
    for ( const ModelInfo &m : kModels )
      if ( m.id == modelId )
        return m.name;
    return {};
  }

  fs::path ColmapModel::modelFolder( const fs::path &path, bool *binary )
  {
    fs::path folder = path;
    std::error_code ec;
    if ( !fs::is_directory( path, ec ) )
      folder = path.parent_path().empty() ? fs::path( "." ) : path.parent_path();
    const bool hasBinary = fs::exists( folder / "cameras.bin", ec ) && fs::exists( folder / "images.bin", ec );
    const bool hasText = fs::exists( folder / "cameras.txt", ec ) && fs::exists( folder / "images.txt", ec );
    if ( binary )
      *binary = hasBinary;
    if ( !hasBinary && !hasText )
    {
      if ( !fs::exists( path, ec ) )
        throw ColmapFormatError( "the COLMAP model " + path.string() + " does not exist" );
      throw ColmapFormatError( "the folder " + folder.string() + " holds no COLMAP model: cameras.txt and images.txt (or cameras.bin and images.bin) are missing" );
    }
    return folder;
  }

  bool ColmapModel::isModel( const fs::path &path )
  {
    try
    {
      modelFolder( path );
      return true;
    }
    catch ( const ColmapFormatError & )
    {
      return false;
    }
  }

  ColmapModel ColmapModel::read( const fs::path &path )
  {
    bool binary = false;
    const fs::path folder = modelFolder( path, &binary );
    ColmapModel model;
    std::error_code ec;
    if ( binary )
    {
      model.cameras = readCamerasBinary( folder / "cameras.bin" );
      model.images = readImagesBinary( folder / "images.bin" );
      if ( fs::exists( folder / "points3D.bin", ec ) )
        model.points3D = readPointsBinary( folder / "points3D.bin" );
    }
    else
    {
      model.cameras = readCamerasText( folder / "cameras.txt" );
      model.images = readImagesText( folder / "images.txt" );
      if ( fs::exists( folder / "points3D.txt", ec ) )
        model.points3D = readPointsText( folder / "points3D.txt" );
    }
    const std::string extension = binary ? ".bin" : ".txt";
    if ( fs::exists( folder / ( "rigs" + extension ), ec ) )
      model.rigs = readColmapRigs( folder / ( "rigs" + extension ), binary );
    if ( fs::exists( folder / ( "frames" + extension ), ec ) )
      model.frames = readColmapFrames( folder / ( "frames" + extension ), binary );
    return model;
  }

  const ColmapCamera *ColmapModel::findCamera( std::uint32_t id ) const
  {
    for ( const ColmapCamera &c : cameras )
      if ( c.id == id )
        return &c;
    return nullptr;
  }

  void ColmapModel::writeText( const fs::path &folder ) const
  {
    std::error_code ec;
    fs::create_directories( folder, ec );
    {
      const fs::path file = folder / "cameras.txt";
      std::ofstream out = openForWriting( file, false );
      out << "# Camera list with one line of data per camera:\n#   CAMERA_ID, MODEL, WIDTH, HEIGHT, PARAMS[]\n";
      out << "# Number of cameras: " << cameras.size() << "\n";
      for ( const ColmapCamera &c : cameras )
      {
        out << c.id << ' ' << c.model << ' ' << c.width << ' ' << c.height;
        for ( double p : c.params )
          out << ' ' << p;
        out << '\n';
      }
      finish( out, file );
    }
    {
      const fs::path file = folder / "images.txt";
      std::ofstream out = openForWriting( file, false );
      out << "# Image list with two lines of data per image:\n#   IMAGE_ID, QW, QX, QY, QZ, TX, TY, TZ, CAMERA_ID, NAME\n#   POINTS2D[] as (X, Y, POINT3D_ID)\n";
      out << "# Number of images: " << images.size() << "\n";
      for ( const ColmapImage &im : images )
      {
        out << im.id << ' ' << im.qvec[0] << ' ' << im.qvec[1] << ' ' << im.qvec[2] << ' ' << im.qvec[3] << ' '
            << im.tvec[0] << ' ' << im.tvec[1] << ' ' << im.tvec[2] << ' ' << im.cameraId << ' ' << im.name << '\n';
        for ( size_t i = 0; i < im.points2D.size(); ++i )
          out << ( i ? " " : "" ) << im.points2D[i].pixel.x() << ' ' << im.points2D[i].pixel.y() << ' ' << im.points2D[i].point3DId;
        out << '\n';
      }
      finish( out, file );
    }
    {
      const fs::path file = folder / "points3D.txt";
      std::ofstream out = openForWriting( file, false );
      out << "# 3D point list with one line of data per point:\n#   POINT3D_ID, X, Y, Z, R, G, B, ERROR, TRACK[] as (IMAGE_ID, POINT2D_IDX)\n";
      out << "# Number of points: " << points3D.size() << "\n";
      for ( const ColmapPoint3D &p : points3D )
      {
        out << p.id << ' ' << p.xyz[0] << ' ' << p.xyz[1] << ' ' << p.xyz[2] << ' '
            << int( p.rgb[0] ) << ' ' << int( p.rgb[1] ) << ' ' << int( p.rgb[2] ) << ' ' << p.error;
        for ( const ColmapTrackElement &t : p.track )
          out << ' ' << t.imageId << ' ' << t.point2DIndex;
        out << '\n';
      }
      finish( out, file );
    }
    writeRigsAndFrames( folder, false );
  }

  void ColmapModel::writeRigsAndFrames( const fs::path &folder, bool binary ) const
  {
    const std::string extension = binary ? ".bin" : ".txt";
    std::error_code ec;
    if ( rigs.empty() )
      fs::remove( folder / ( "rigs" + extension ), ec );
    else
      writeColmapRigs( rigs, folder / ( "rigs" + extension ), binary );
    if ( frames.empty() )
      fs::remove( folder / ( "frames" + extension ), ec );
    else
      writeColmapFrames( frames, folder / ( "frames" + extension ), binary );
  }

  void ColmapModel::writeBinary( const fs::path &folder ) const
  {
    std::error_code ec;
    fs::create_directories( folder, ec );
    {
      const fs::path file = folder / "cameras.bin";
      std::ofstream out = openForWriting( file, true );
      put<std::uint64_t>( out, cameras.size() );
      for ( const ColmapCamera &c : cameras )
      {
        const int modelId = colmapCameraModelId( c.model );
        if ( modelId < 0 || static_cast<int>( c.params.size() ) != colmapCameraModelParameterCount( c.model ) )
          throw std::runtime_error( "camera " + std::to_string( c.id ) + " has model '" + c.model + "' with " + std::to_string( c.params.size() ) + " parameters, which COLMAP cannot store" );
        put<std::uint32_t>( out, c.id );
        put<std::int32_t>( out, modelId );
        put<std::uint64_t>( out, c.width );
        put<std::uint64_t>( out, c.height );
        for ( double p : c.params )
          put<double>( out, p );
      }
      finish( out, file );
    }
    {
      const fs::path file = folder / "images.bin";
      std::ofstream out = openForWriting( file, true );
      put<std::uint64_t>( out, images.size() );
      for ( const ColmapImage &im : images )
      {
        put<std::uint32_t>( out, im.id );
        for ( int i = 0; i < 4; ++i )
          put<double>( out, im.qvec[i] );
        for ( int i = 0; i < 3; ++i )
          put<double>( out, im.tvec[i] );
        put<std::uint32_t>( out, im.cameraId );
        out.write( im.name.c_str(), static_cast<std::streamsize>( im.name.size() + 1 ) );
        put<std::uint64_t>( out, im.points2D.size() );
        for ( const ColmapPoint2D &p : im.points2D )
        {
          put<double>( out, p.pixel.x() );
          put<double>( out, p.pixel.y() );
          put<std::uint64_t>( out, p.point3DId < 0 ? std::numeric_limits<std::uint64_t>::max() : static_cast<std::uint64_t>( p.point3DId ) );
        }
      }
      finish( out, file );
    }
    {
      const fs::path file = folder / "points3D.bin";
      std::ofstream out = openForWriting( file, true );
      put<std::uint64_t>( out, points3D.size() );
      for ( const ColmapPoint3D &p : points3D )
      {
        put<std::uint64_t>( out, p.id );
        for ( int i = 0; i < 3; ++i )
          put<double>( out, p.xyz[i] );
        for ( int i = 0; i < 3; ++i )
          put<std::uint8_t>( out, p.rgb[i] );
        put<double>( out, p.error );
        put<std::uint64_t>( out, p.track.size() );
        for ( const ColmapTrackElement &t : p.track )
        {
          put<std::uint32_t>( out, t.imageId );
          put<std::uint32_t>( out, t.point2DIndex );
        }
      }
      finish( out, file );
    }
    writeRigsAndFrames( folder, true );
  }

} // namespace geostation

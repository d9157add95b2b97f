/***************************************************************************
  opencvcalibration.cpp - cameras from OpenCV calibration files
 ***************************************************************************/
#include "io/opencvcalibration.h"

#include <cmath>
#include <fstream>
#include <iterator>
#include <optional>
#include <sstream>
#include <stdexcept>

#include <opencv2/core/persistence.hpp>

#include "io/textfile.h"

namespace fs = std::filesystem;

namespace geostation
{
  namespace
  {
    [[noreturn]] void fail( const fs::path &file, const std::string &problem )
    {
      throw std::invalid_argument( "the calibration file " + file.string() + ": " + problem );
    }

    //! Larger than any calibration file (a few kB for a rig of cameras).
    constexpr size_t kMaxFileBytes = 1 << 20;

    //! More values than any calibration matrix (3 x 3, up to 14 distortion coefficients) has.
    constexpr long long kMaxMatrixValues = 64;

    std::vector<double> numbers( const cv::FileNode &node, const fs::path &file, const std::string &key )
    {
      std::vector<double> values;
      if ( node.isMap() && !node["data"].empty() ) // an opencv-matrix
      {
        // OpenCV allocates rows x cols before it reads the data: a corrupt size would take gigabytes
        const int rows = static_cast<int>( node["rows"] ), cols = static_cast<int>( node["cols"] );
        if ( rows <= 0 || cols <= 0 || static_cast<long long>( rows ) * cols > kMaxMatrixValues || static_cast<long long>( rows ) * cols != static_cast<long long>( node["data"].size() ) )
          fail( file, "\"" + key + "\" is an opencv-matrix of " + std::to_string( rows ) + " x " + std::to_string( cols ) + " with " + std::to_string( node["data"].size() ) +
                " values (a calibration's matrices have at most " + std::to_string( kMaxMatrixValues ) + ")" );
        cv::Mat m;
        node >> m;
        m.convertTo( m, CV_64F );
        values.assign( m.begin<double>(), m.end<double>() );
      }
      else if ( node.isSeq() )
        for ( const cv::FileNode &n : node )
        {
          if ( !n.isReal() && !n.isInt() )
            fail( file, "\"" + key + "\" holds something that is not a number" );
          values.push_back( static_cast<double>( n ) );
        }
      else
        fail( file, "\"" + key + "\" is not a matrix or a list of numbers" );
      for ( double v : values )
        if ( !std::isfinite( v ) )
          fail( file, "\"" + key + "\" holds a value that is not a number" );
      return values;
    }

    RigCamera rigCamera( const cv::FileNode &node, const std::string &id, const fs::path &file )
    {
      const char *required[] = { "camera_matrix", "distortion_coefficients", "image_width", "image_height" };
      for ( const char *key : required )
        if ( node[key].empty() )
          fail( file, "camera \"" + id + "\" has no \"" + key + "\" (an OpenCV calibration has camera_matrix, distortion_coefficients, image_width, image_height)" );
      const std::vector<double> k = numbers( node["camera_matrix"], file, "camera_matrix" );
      if ( k.size() != 9 )
        fail( file, "\"camera_matrix\" of camera \"" + id + "\" has " + std::to_string( k.size() ) + " values, not 3 x 3" );
      Eigen::Matrix3d cameraMatrix;
      cameraMatrix << k[0], k[1], k[2], k[3], k[4], k[5], k[6], k[7], k[8];
      const std::vector<double> distortion = numbers( node["distortion_coefficients"], file, "distortion_coefficients" );
      RigCamera rig;
      try
      {
        rig.camera = cameraFromOpenCv( id, cameraMatrix, distortion,
                                       static_cast<int>( node["image_width"] ), static_cast<int>( node["image_height"] ) );
      }
      catch ( const std::invalid_argument &e )
      {
        fail( file, e.what() );
      }
      for ( const auto &[key, target] : { std::make_pair( "lever_arm", &rig.leverArmM ), std::make_pair( "boresight", &rig.boresightDeg ) } )
        if ( !node[key].empty() )
        {
          const std::vector<double> v = numbers( node[key], file, key );
          if ( v.size() != 3 )
            fail( file, "\"" + std::string( key ) + "\" of camera \"" + id + "\" needs three values" );
          *target = Eigen::Vector3d( v[0], v[1], v[2] );
        }
      if ( !node["image_pattern"].empty() )
        rig.imagePattern = static_cast<std::string>( node["image_pattern"] );
      return rig;
    }

    /**
     * OpenCV's YAML parser also loops for ever on a line indented left of
     * the first key (the top level), on anything after a document end
     * marker ("...-") and on a key on the document start's line followed by
     * a line such as "--a-" ("--- a: 5"): refused first, naming the line.
     * (Found by fuzzing OpenCV 4.6; a YAML file OpenCV writes has none of
     * them: its "---" stands alone.)
     */
    void requireYamlIndentation( const fs::path &file, const std::string &text )
    {
      std::istringstream lines( text );
      std::string line;
      int number = 0;
      std::optional<size_t> topLevel;
      while ( std::getline( lines, line ) )
      {
        ++number;
        const size_t first = line.find_first_not_of( " \t\r" );
        if ( first == std::string::npos || line[first] == '#' || line[first] == '%' )
          continue;
        if ( line.compare( first, 3, "---" ) == 0 || line.compare( first, 3, "..." ) == 0 )
        {
          // a document marker; anything after it but blanks (e.g. "...-", "--- a: 5") can send the parser into a loop
          if ( line.find_first_not_of( " \t\r", first + 3 ) != std::string::npos )
            fail( file, "line " + std::to_string( number ) + " has something after the document marker \"" + line.substr( first, 3 ) +
                  "\" on its line: not YAML OpenCV can read" );
          continue;
        }
        if ( !topLevel )
          topLevel = first;
        else if ( first < *topLevel )
          fail( file, "line " + std::to_string( number ) + " is indented left of the first key: not YAML OpenCV can read" );
      }
    }

    cv::FileStorage open( const fs::path &file )
    {
      std::error_code ec;
      if ( !fs::is_regular_file( file, ec ) )
        throw std::invalid_argument( "the calibration file " + file.string() + " does not exist" );
      const std::string ext = asciiLower( file.extension().string() );
      if ( ext != ".yaml" && ext != ".yml" && ext != ".xml" )
        fail( file, "not an OpenCV calibration (expected a .yaml, .yml or .xml file)" );
      // OpenCV's parser loops for ever on some bytes that are no text (a NUL inside the file): a calibration is small text
      std::ifstream in( file, std::ios::binary );
      const std::string bytes( ( std::istreambuf_iterator<char>( in ) ), std::istreambuf_iterator<char>() );
      if ( bytes.size() > kMaxFileBytes )
        fail( file, "more than 1 MB: not a camera calibration" );
      if ( bytes.find( '\0' ) != std::string::npos )
        fail( file, "not text (it holds NUL bytes)" );
      if ( ext != ".xml" )
        requireYamlIndentation( file, bytes );
      cv::FileStorage fsr;
      try
      {
        fsr.open( file.string(), cv::FileStorage::READ );
      }
      catch ( const std::exception & )
      {
        // cv::Exception from OpenCV's parser, or std::length_error from a corrupt length in it: not readable
        fsr.release();
      }
      if ( !fsr.isOpened() )
        fail( file, "not readable as an OpenCV FileStorage (YAML must start with %YAML:1.0)" );
      return fsr;
    }
  } // namespace

  Camera cameraFromOpenCv( const std::string &id, const Eigen::Matrix3d &cameraMatrix, const std::vector<double> &distortion, int width, int height )
  {
    if ( width <= 0 || height <= 0 )
      throw std::invalid_argument( "camera \"" + id + "\" has no image size (image_width, image_height)" );
    if ( cameraMatrix( 0, 1 ) != 0.0 || cameraMatrix( 1, 0 ) != 0.0 || cameraMatrix.row( 2 ) != Eigen::RowVector3d( 0, 0, 1 ) )
      throw std::invalid_argument( "camera \"" + id + "\": the camera matrix has skew or is not [fx 0 cx; 0 fy cy; 0 0 1], which GeoStation's cameras cannot represent" );
    if ( !( cameraMatrix( 0, 0 ) > 0.0 ) || !( cameraMatrix( 1, 1 ) > 0.0 ) )
      throw std::invalid_argument( "camera \"" + id + "\": the focal lengths of the camera matrix are not positive" );
    const size_t n = distortion.size();
    if ( n != 0 && n != 4 && n != 5 && n != 8 && n != 12 && n != 14 )
      throw std::invalid_argument( "camera \"" + id + "\" has " + std::to_string( n ) + " distortion coefficients; OpenCV writes 4, 5, 8, 12 or 14" );
    for ( size_t i = 5; i < n; ++i )
      if ( distortion[i] != 0.0 )
        throw std::invalid_argument( "camera \"" + id + "\" uses OpenCV's rational, thin-prism or tilt terms (coefficient " + std::to_string( i + 1 )
                                     + " is not 0), which GeoStation's lens models cannot represent exactly" );
    Camera camera;
    camera.id = id;
    camera.width = width;
    camera.height = height;
    camera.f = cameraMatrix( 0, 0 );
    camera.aspect = cameraMatrix( 1, 1 ) / cameraMatrix( 0, 0 );
    camera.cx = cameraMatrix( 0, 2 ) + 0.5; // OpenCV's pixel centres are integers
    camera.cy = cameraMatrix( 1, 2 ) + 0.5;
    if ( n > 0 )
    {
      camera.distortion.model = DistortionModel::OpenCV;
      for ( size_t i = 0; i < std::min<size_t>( n, kDistortionCoefficientCount ); ++i )
        camera.distortion.coeffs[i] = distortion[i];
    }
    return camera;
  }

  namespace
  {
    std::vector<RigCamera> readCameras( const fs::path &file )
    {
      cv::FileStorage fsr = open( file );
      std::vector<RigCamera> cameras;
      const cv::FileNode rig = fsr["cameras"];
      if ( !rig.empty() )
      {
        if ( !rig.isSeq() || rig.size() == 0 )
          fail( file, "\"cameras\" must be a non-empty sequence of cameras" );
        for ( const cv::FileNode &node : rig )
        {
          if ( node["id"].empty() )
            fail( file, "camera " + std::to_string( cameras.size() + 1 ) + " of \"cameras\" has no \"id\"" );
          const std::string id = static_cast<std::string>( node["id"] );
          if ( id.empty() )
            fail( file, "camera " + std::to_string( cameras.size() + 1 ) + " of \"cameras\" has an \"id\" that is empty or not text" );
          for ( const RigCamera &c : cameras )
            if ( c.camera.id == id )
              fail( file, "the camera id \"" + id + "\" is used twice" );
          cameras.push_back( rigCamera( node, id, file ) );
        }
      }
      else if ( !fsr["camera_matrix"].empty() )
        cameras.push_back( rigCamera( fsr.root(), file.stem().string(), file ) );
      else
        fail( file, "neither \"camera_matrix\" (one camera) nor \"cameras\" (a rig) is in it" );
      return cameras;
    }
  } // namespace

  std::vector<RigCamera> readOpenCvCalibration( const fs::path &file )
  {
    try
    {
      return readCameras( file );
    }
    catch ( const cv::Exception &e )
    {
      // OpenCV's own checks while reading a node (e.g. an opencv-matrix whose data does not fit rows x cols)
      fail( file, "OpenCV cannot read it (" + e.err + ")" );
    }
  }

  bool isOpenCvCalibration( const fs::path &file )
  {
    try
    {
      cv::FileStorage fsr = open( file );
      return !fsr["camera_matrix"].empty() || !fsr["cameras"].empty();
    }
    catch ( const std::exception & )
    {
      return false;
    }
  }

} // namespace geostation

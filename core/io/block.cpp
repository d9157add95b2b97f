/***************************************************************************
  block.cpp - reading, validating and writing *.geostation.json
 ***************************************************************************/
#include "io/block.h"

#include <fstream>
#include <regex>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include <cpl_error.h>
#include <gdal.h>

#include "geometry/crs.h"
#include "io/textfile.h"
#include "io/internal/jsonnode.h"
#include "io/rasterfile.h"

namespace geostation
{

  namespace
  {
    using json = nlohmann::json;

    const char *kFormatName = "geostation-block";
    constexpr int kFormatVersion = 1;

    //! The object without the given keys: what the loader does not interpret.
    json unknownKeys( const json &object, std::initializer_list<const char *> known )
    {
      json rest = object;
      for ( const char *key : known )
        rest.erase( key );
      return rest;
    }

    //! extraJson with known written over it (nested objects merged key by key).
    json withKnown( const std::string &extraJson, const json &known )
    {
      json out = json::parse( extraJson.empty() ? std::string( "{}" ) : extraJson, nullptr, false );
      if ( !out.is_object() )
        out = json::object();
      out.merge_patch( known );
      return out;
    }

    Distortion readDistortion( const JsonNode &node, json *extraOut )
    {
      node.requireObject();
      Distortion d;
      const std::string modelName = node.child( "model" ).string();
      const std::optional<DistortionModel> model = distortionModelFromName( modelName );
      if ( !model )
        node.child( "model" ).fail( "expected one of \"none\", \"opencv\", \"brown_photo\", found \"" + modelName + "\"" );
      d.model = *model;
      const char *names[kDistortionCoefficientCount] = { "k1", "k2", "p1", "p2", "k3" };
      for ( int i = 0; i < kDistortionCoefficientCount; ++i )
        if ( node.has( names[i] ) )
          d.coeffs[i] = node.child( names[i] ).number( "distortion coefficient" );
      *extraOut = unknownKeys( node.value(), { "model", "k1", "k2", "p1", "p2", "k3" } );
      return d;
    }

    Camera readCamera( const JsonNode &node, json *extraOut )
    {
      node.requireObject();
      Camera c;
      c.id = node.child( "id" ).string();
      c.width = node.child( "width" ).positiveInteger( "image width in pixels" );
      c.height = node.child( "height" ).positiveInteger( "image height in pixels" );
      c.f = node.child( "f" ).positiveNumber( "principal distance in pixels" );
      if ( node.has( "aspect" ) )
        c.aspect = node.child( "aspect" ).positiveNumber( "fy / fx" );
      c.cx = node.child( "cx" ).number( "principal point column in pixels" );
      c.cy = node.child( "cy" ).number( "principal point row in pixels" );
      if ( node.has( "pixel_size_mm" ) )
        c.pixelSizeMm = node.child( "pixel_size_mm" ).positiveNumber( "pixel size in mm" );
      if ( node.has( "fiducials" ) )
      {
        std::set<std::string> ids;
        for ( const JsonNode &item : node.child( "fiducials" ).arrayItems( true, "fiducials" ) )
        {
          item.requireObject();
          Fiducial f;
          f.id = item.child( "id" ).string();
          if ( !ids.insert( f.id ).second )
            item.child( "id" ).fail( "the fiducial id \"" + f.id + "\" is used twice" );
          f.photoMm = { item.child( "x_mm" ).number( "photo x in mm" ), item.child( "y_mm" ).number( "photo y in mm" ) };
          c.fiducials.push_back( f );
        }
      }
      json extra = unknownKeys( node.value(), { "id", "width", "height", "f", "aspect", "cx", "cy", "pixel_size_mm", "distortion", "fiducials" } );
      if ( node.has( "distortion" ) )
      {
        json distortionExtra;
        c.distortion = readDistortion( node.child( "distortion" ), &distortionExtra );
        if ( !distortionExtra.empty() )
          extra["distortion"] = distortionExtra;
      }
      if ( c.distortion.model == DistortionModel::BrownPhoto && !c.pixelSizeMm )
        node.fail( "the brown_photo distortion model needs \"pixel_size_mm\" (its coefficients are in mm)" );
      *extraOut = extra;
      return c;
    }

    Station readStation( const JsonNode &node )
    {
      static const std::regex isoTime( R"(^\d{4}-\d{2}-\d{2}T\d{2}:\d{2}:\d{2}(\.\d+)?(Z|[+-]\d{2}:?\d{2})?$)" );
      node.requireObject();
      Station s;
      s.id = node.child( "id" ).string();
      if ( node.has( "time" ) )
      {
        s.time = node.child( "time" ).string();
        if ( !std::regex_match( s.time, isoTime ) )
          node.child( "time" ).fail( "expected an ISO 8601 time such as \"2025-05-01T10:00:00.000Z\", found \"" + s.time + "\"" );
      }
      if ( node.has( "trajectory" ) )
        s.trajectory = node.child( "trajectory" ).string( true );
      s.extraJson = unknownKeys( node.value(), { "id", "time", "trajectory" } ).dump();
      return s;
    }

    const char *kExteriorKeys[6] = { "X", "Y", "Z", "omega", "phi", "kappa" };

    BlockImage readImage( const JsonNode &node )
    {
      node.requireObject();
      BlockImage image;
      image.id = node.child( "id" ).string();
      image.cameraId = node.child( "camera" ).string();
      if ( node.has( "station" ) )
        image.stationId = node.child( "station" ).string();
      image.path = node.child( "path" ).string();

      int present = 0;
      std::string missing;
      for ( const char *key : kExteriorKeys )
      {
        if ( node.has( key ) )
          ++present;
        else
          missing += std::string( missing.empty() ? "" : ", " ) + key;
      }
      if ( present > 0 && present < 6 )
        node.fail( "an oriented image needs all six exterior values X, Y, Z, omega, phi, kappa; missing: " + missing );
      if ( present == 6 )
      {
        ExteriorOrientation eo;
        eo.projectionCentre = { node.child( "X" ).number( "projection centre X in metres" ),
                                node.child( "Y" ).number( "projection centre Y in metres" ),
                                node.child( "Z" ).number( "projection centre Z in metres" )
                              };
        eo.omegaDeg = node.child( "omega" ).number( "omega in degrees" );
        eo.phiDeg = node.child( "phi" ).number( "phi in degrees" );
        eo.kappaDeg = node.child( "kappa" ).number( "kappa in degrees" );
        if ( node.has( "sigma" ) )
        {
          const JsonNode sigmaNode = node.child( "sigma" );
          sigmaNode.requireObject();
          ExteriorSigma sigma;
          double *targets[6] = { &sigma.x, &sigma.y, &sigma.z, &sigma.omegaDeg, &sigma.phiDeg, &sigma.kappaDeg };
          const char *meanings[6] = { "metres", "metres", "metres", "degrees", "degrees", "degrees" };
          for ( int i = 0; i < 6; ++i )
            *targets[i] = sigmaNode.child( kExteriorKeys[i] ).positiveNumber( std::string( "standard deviation in " ) + meanings[i], true );
          eo.sigma = sigma;
        }
        image.exterior = eo;
      }
      else if ( node.has( "sigma" ) )
      {
        node.child( "sigma" ).fail( "sigmas are given but the image has no exterior orientation" );
      }
      if ( node.has( "inner_orientation" ) )
      {
        const JsonNode io = node.child( "inner_orientation" );
        io.requireObject();
        const std::vector<JsonNode> rows = io.child( "photo_from_pixel" ).arrayItems( false, "two rows" );
        if ( rows.size() != 2 )
          io.child( "photo_from_pixel" ).fail( "expected two rows of three numbers (photo mm from col, row, 1)" );
        ImageInnerOrientation inner;
        for ( int r = 0; r < 2; ++r )
        {
          const std::vector<JsonNode> values = rows[r].arrayItems( false, "three numbers" );
          if ( values.size() != 3 )
            rows[r].fail( "expected three numbers" );
          for ( int c = 0; c < 3; ++c )
            inner.photoFromPixel( r, c ) = values[c].number( "affine coefficient" );
        }
        if ( io.has( "sigma0_mm" ) )
          inner.sigma0Mm = io.child( "sigma0_mm" ).positiveNumber( "mm", true );
        image.innerOrientation = inner;
      }
      image.extraJson = unknownKeys( node.value(), { "id", "camera", "station", "path", "X", "Y", "Z", "omega", "phi", "kappa", "sigma", "inner_orientation" } ).dump();
      return image;
    }

    template <typename T>
    void requireUniqueIds( const std::vector<T> &items, const std::vector<JsonNode> &nodes, const std::string &what )
    {
      std::set<std::string> seen;
      for ( size_t i = 0; i < items.size(); ++i )
        if ( !seen.insert( items[i].id ).second )
          nodes[i].child( "id" ).fail( "the " + what + " id \"" + items[i].id + "\" is used twice" );
    }

    std::string joinIds( const std::vector<std::string> &ids )
    {
      std::string out;
      for ( size_t i = 0; i < ids.size() && i < 12; ++i )
        out += ( i ? ", " : "" ) + ids[i];
      if ( ids.size() > 12 )
        out += ", ... (" + std::to_string( ids.size() ) + " in all)";
      return out;
    }

    //! Line and column (1-based) of a byte offset, for JSON syntax errors.
    std::pair<size_t, size_t> lineColumn( const std::string &text, size_t byte )
    {
      size_t line = 1, column = 1;
      for ( size_t i = 0; i < byte && i < text.size(); ++i )
      {
        if ( text[i] == '\n' )
        {
          ++line;
          column = 1;
        }
        else
          ++column;
      }
      return { line, column };
    }
  } // namespace

  BlockFormatError::BlockFormatError( const std::string &file, const std::string &jsonPath, const std::string &problem )
    : std::runtime_error( file + ": " + ( jsonPath.empty() ? std::string() : "at " + jsonPath + ": " ) + problem )
    , mFile( file )
    , mJsonPath( jsonPath )
    , mProblem( problem )
  {}

  Block Block::load( const std::filesystem::path &file )
  {
    std::ifstream in( file, std::ios::binary );
    if ( !in )
    {
      const std::string why = std::filesystem::exists( file ) ? "it cannot be opened for reading" : "the file does not exist";
      throw BlockFormatError( file.string(), "", why );
    }
    std::stringstream buffer;
    buffer << in.rdbuf();
    return fromJsonText( buffer.str(), file );
  }

  Block Block::fromJsonText( const std::string &text, const std::filesystem::path &file )
  {
    const std::string fileName = file.string();
    json root;
    try
    {
      root = json::parse( text );
    }
    catch ( const json::parse_error &e )
    {
      const auto [line, column] = lineColumn( text, e.byte > 0 ? e.byte - 1 : 0 );
      throw BlockFormatError( fileName, "", "not valid JSON (line " + std::to_string( line ) + ", column " + std::to_string( column ) + ")" );
    }
    catch ( const json::out_of_range & )
    {
      // e.g. 1e400: the parser gives no position for it
      throw BlockFormatError( fileName, "", "not valid JSON: a number is too large to be read" );
    }

    const JsonNode top( root, "$", fileName );
    top.requireObject();
    const JsonNode format = top.child( "format" );
    if ( format.string() != kFormatName )
      format.fail( std::string( "expected \"" ) + kFormatName + "\", found \"" + format.string() + "\"" );
    const JsonNode version = top.child( "version" );
    if ( !version.value().is_number_integer() )
      version.fail( "expected the whole number 1, found " + describeJsonType( version.value() ) );
    if ( version.value().get<long long>() != kFormatVersion )
      version.fail( "this GeoStation reads block version " + std::to_string( kFormatVersion ) + ", found version " + version.value().dump() );

    Block block;
    block.sourceFile = file;
    const JsonNode crsNode = top.child( "crs" );
    block.crs = crsNode.string();
    try
    {
      requireProjectedMetricCrs( block.crs );
    }
    catch ( const std::invalid_argument &e )
    {
      crsNode.fail( e.what() );
    }

    const std::vector<JsonNode> cameraNodes = top.child( "cameras" ).arrayItems( false, "cameras" );
    for ( const JsonNode &node : cameraNodes )
    {
      json extra;
      block.cameras.push_back( readCamera( node, &extra ) );
      block.cameraExtraJson[block.cameras.back().id] = extra.dump();
    }
    requireUniqueIds( block.cameras, cameraNodes, "camera" );

    std::vector<JsonNode> stationNodes;
    if ( top.has( "stations" ) )
      stationNodes = top.child( "stations" ).arrayItems( true, "stations" );
    for ( const JsonNode &node : stationNodes )
      block.stations.push_back( readStation( node ) );
    requireUniqueIds( block.stations, stationNodes, "station" );

    const std::vector<JsonNode> imageNodes = top.child( "images" ).arrayItems( true, "images" );
    for ( const JsonNode &node : imageNodes )
      block.images.push_back( readImage( node ) );
    requireUniqueIds( block.images, imageNodes, "image" );

    std::vector<std::string> cameraIds, stationIds;
    for ( const Camera &c : block.cameras )
      cameraIds.push_back( c.id );
    for ( const Station &s : block.stations )
      stationIds.push_back( s.id );
    for ( size_t i = 0; i < block.images.size(); ++i )
    {
      const BlockImage &image = block.images[i];
      if ( !block.findCamera( image.cameraId ) )
        imageNodes[i].child( "camera" ).fail( "camera \"" + image.cameraId + "\" is not defined in $.cameras (defined: " + joinIds( cameraIds ) + ")" );
      if ( !image.stationId.empty() && !block.findStation( image.stationId ) )
        imageNodes[i].child( "station" ).fail( "station \"" + image.stationId + "\" is not defined in $.stations" + ( stationIds.empty() ? std::string() : " (defined: " + joinIds( stationIds ) + ")" ) );
    }

    block.extraJson = unknownKeys( root, { "format", "version", "crs", "cameras", "stations", "images" } ).dump();
    return block;
  }

  std::string Block::toJsonText() const
  {
    json root = withKnown( extraJson, json::object() );
    root["format"] = kFormatName;
    root["version"] = kFormatVersion;
    root["crs"] = crs;

    json cameraArray = json::array();
    for ( const Camera &c : cameras )
    {
      json known = { { "id", c.id }, { "width", c.width }, { "height", c.height }, { "f", c.f }, { "aspect", c.aspect }, { "cx", c.cx }, { "cy", c.cy } };
      if ( c.pixelSizeMm )
        known["pixel_size_mm"] = *c.pixelSizeMm;
      if ( !c.fiducials.empty() )
      {
        json fiducials = json::array();
        for ( const Fiducial &f : c.fiducials )
          fiducials.push_back( { { "id", f.id }, { "x_mm", f.photoMm.x() }, { "y_mm", f.photoMm.y() } } );
        known["fiducials"] = fiducials;
      }
      known["distortion"] = { { "model", distortionModelName( c.distortion.model ) }, { "k1", c.distortion.k1() }, { "k2", c.distortion.k2() }, { "p1", c.distortion.p1() }, { "p2", c.distortion.p2() }, { "k3", c.distortion.k3() } };
      const auto extraIt = cameraExtraJson.find( c.id );
      cameraArray.push_back( withKnown( extraIt != cameraExtraJson.end() ? extraIt->second : std::string( "{}" ), known ) );
    }
    root["cameras"] = cameraArray;

    json stationArray = json::array();
    for ( const Station &s : stations )
    {
      json known = { { "id", s.id } };
      if ( !s.time.empty() )
        known["time"] = s.time;
      if ( !s.trajectory.empty() )
        known["trajectory"] = s.trajectory;
      stationArray.push_back( withKnown( s.extraJson, known ) );
    }
    root["stations"] = stationArray;

    json imageArray = json::array();
    for ( const BlockImage &image : images )
    {
      json known = { { "id", image.id }, { "camera", image.cameraId }, { "path", image.path } };
      if ( !image.stationId.empty() )
        known["station"] = image.stationId;
      if ( image.exterior )
      {
        const ExteriorOrientation &eo = *image.exterior;
        known["X"] = eo.projectionCentre.x();
        known["Y"] = eo.projectionCentre.y();
        known["Z"] = eo.projectionCentre.z();
        known["omega"] = eo.omegaDeg;
        known["phi"] = eo.phiDeg;
        known["kappa"] = eo.kappaDeg;
        if ( eo.sigma )
          known["sigma"] = { { "X", eo.sigma->x }, { "Y", eo.sigma->y }, { "Z", eo.sigma->z }, { "omega", eo.sigma->omegaDeg }, { "phi", eo.sigma->phiDeg }, { "kappa", eo.sigma->kappaDeg } };
      }
      if ( image.innerOrientation )
      {
        const Eigen::Matrix<double, 2, 3> &m = image.innerOrientation->photoFromPixel;
        known["inner_orientation"] = { { "photo_from_pixel", { { m( 0, 0 ), m( 0, 1 ), m( 0, 2 ) }, { m( 1, 0 ), m( 1, 1 ), m( 1, 2 ) } } },
          { "sigma0_mm", image.innerOrientation->sigma0Mm }
        };
      }
      imageArray.push_back( withKnown( image.extraJson, known ) );
    }
    root["images"] = imageArray;
    return root.dump( 2 ) + "\n";
  }

  void Block::save( const std::filesystem::path &file ) const
  {
    // Image paths are relative to the block file: written elsewhere, they are
    // rebased so they still name the same files.
    Block rebased = *this;
    if ( !sourceFile.empty() )
    {
      const std::filesystem::path oldDir = std::filesystem::absolute( sourceFile ).parent_path();
      const std::filesystem::path newDir = std::filesystem::absolute( file ).parent_path();
      if ( oldDir.lexically_normal() != newDir.lexically_normal() )
        for ( BlockImage &image : rebased.images )
          if ( std::filesystem::path( image.path ).is_relative() )
            image.path = ( oldDir / image.path ).lexically_normal().lexically_relative( newDir.lexically_normal() ).generic_string();
    }
    writeTextFileAtomically( file, rebased.toJsonText(), "the block file" );
  }

  Eigen::Matrix<double, 2, 3> nominalFromScanAffine( const Camera &camera, const ImageInnerOrientation &innerOrientation )
  {
    if ( !camera.pixelSizeMm || !( *camera.pixelSizeMm > 0.0 ) )
      throw std::invalid_argument( "camera " + camera.id + " needs pixel_size_mm to use an image's inner orientation" );
    const double ps = *camera.pixelSizeMm;
    Eigen::Matrix<double, 2, 3> nominalFromPhoto;
    nominalFromPhoto << 1.0 / ps, 0.0, camera.cx, 0.0, -camera.aspect / ps, camera.cy;
    Eigen::Matrix3d photoFromPixel = Eigen::Matrix3d::Identity();
    photoFromPixel.topRows<2>() = innerOrientation.photoFromPixel;
    return nominalFromPhoto * photoFromPixel;
  }

  OrientedImage Block::orientedImage( const BlockImage &image ) const
  {
    OrientedImage oriented( cameraOf( image ), requireExterior( image ) );
    if ( image.innerOrientation )
      oriented.setScanAffine( nominalFromScanAffine( cameraOf( image ), *image.innerOrientation ) );
    return oriented;
  }

  const Camera *Block::findCamera( const std::string &cameraId ) const
  {
    for ( const Camera &c : cameras )
      if ( c.id == cameraId )
        return &c;
    return nullptr;
  }

  const BlockImage *Block::findImage( const std::string &imageId ) const
  {
    for ( const BlockImage &image : images )
      if ( image.id == imageId )
        return &image;
    return nullptr;
  }

  const Station *Block::findStation( const std::string &stationId ) const
  {
    for ( const Station &s : stations )
      if ( s.id == stationId )
        return &s;
    return nullptr;
  }

  const Camera &Block::camera( const std::string &cameraId ) const
  {
    if ( const Camera *c = findCamera( cameraId ) )
      return *c;
    std::vector<std::string> ids;
    for ( const Camera &c : cameras )
      ids.push_back( c.id );
    throw std::invalid_argument( "camera \"" + cameraId + "\" is not in the block (cameras: " + joinIds( ids ) + ")" );
  }

  const BlockImage &Block::image( const std::string &imageId ) const
  {
    if ( const BlockImage *image = findImage( imageId ) )
      return *image;
    std::vector<std::string> ids;
    for ( const BlockImage &image : images )
      ids.push_back( image.id );
    throw std::invalid_argument( "image \"" + imageId + "\" is not in the block " + sourceFile.filename().string() + " (images: " + joinIds( ids ) + ")" );
  }

  std::filesystem::path Block::imageFilePath( const BlockImage &image ) const
  {
    const std::filesystem::path p( image.path );
    if ( p.is_absolute() )
      return p;
    return ( sourceFile.has_parent_path() ? sourceFile.parent_path() : std::filesystem::path( "." ) ) / p;
  }

  const ExteriorOrientation &Block::requireExterior( const BlockImage &image ) const
  {
    if ( !image.exterior )
      throw std::invalid_argument( "image \"" + image.id + "\" has no exterior orientation yet; orient it first (resection or bundle adjustment)" );
    return *image.exterior;
  }

  void requireReadableImageFile( const Block &block, const BlockImage &image )
  {
    registerGdalDrivers();

    const std::filesystem::path path = block.imageFilePath( image );
    if ( !std::filesystem::exists( path ) )
      throw std::runtime_error( "the file of image \"" + image.id + "\" does not exist: " + path.string() );
    CPLPushErrorHandler( CPLQuietErrorHandler );
    GDALDatasetH dataset = GDALOpenEx( path.string().c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY, nullptr, nullptr, nullptr );
    CPLPopErrorHandler();
    if ( !dataset )
      throw std::runtime_error( "the file of image \"" + image.id + "\" cannot be decoded as a raster: " + path.string() );
    const int width = GDALGetRasterXSize( dataset );
    const int height = GDALGetRasterYSize( dataset );
    GDALClose( dataset );
    const Camera &camera = block.cameraOf( image );
    if ( width != camera.width || height != camera.height )
      throw std::runtime_error( "the file of image \"" + image.id + "\" is " + std::to_string( width ) + " x " + std::to_string( height ) + " pixels but camera \"" + camera.id + "\" declares " + std::to_string( camera.width ) + " x " + std::to_string( camera.height ) + ": " + path.string() );
  }

} // namespace geostation

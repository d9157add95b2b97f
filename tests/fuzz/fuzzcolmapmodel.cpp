/***************************************************************************
  fuzzcolmapmodel.cpp - COLMAP sparse models, text and binary
  -------------------------------------------------------------------------
  The input holds the model's files, cut at "%%" lines (cameras, images,
  points3D, rigs, frames; an empty part is a file the model does not
  have), text for colmap_text and binary for colmap_binary.
  ColmapModel::read() either throws ColmapFormatError
  with a message or gives a model that, written and read again, writes the
  same files; importColmapModel() (without image files) either throws
  std::invalid_argument with a message or gives a block whose images all
  have their camera. A binary model that reads also writes binary files
  that read back to the same model.
 ***************************************************************************/
#include "fuzztarget.h"

#include <fstream>
#include <iterator>

#include "io/colmapimport.h"
#include "io/colmapmodel.h"

namespace
{
  using geostation::ColmapModel;

  std::string fileText( const std::filesystem::path &file )
  {
    std::ifstream in( file, std::ios::binary );
    return std::string( ( std::istreambuf_iterator<char>( in ) ), std::istreambuf_iterator<char>() );
  }

  //! Fails with the first line that differs when the two files differ.
  void requireSameFile( const std::filesystem::path &a, const std::filesystem::path &b, const std::string &what )
  {
    const std::string textA = fileText( a ), textB = fileText( b );
    if ( textA == textB )
      return;
    std::size_t start = 0;
    while ( start < textA.size() && start < textB.size() && textA[start] == textB[start] )
      ++start;
    start = textA.rfind( '\n', start ) == std::string::npos ? 0 : textA.rfind( '\n', start ) + 1;
    geostation::fuzz::violated( a.filename().string() + " " + what + ", from the line\n" + textA.substr( start, textA.find( '\n', start ) - start ) + "\nto\n" +
                                textB.substr( start, textB.find( '\n', start ) - start ) );
  }

  int runColmapModel( const std::uint8_t *data, std::size_t size, bool binary )
  {
    namespace fuzz = geostation::fuzz;
    const std::filesystem::path folder = fuzz::scratchFolder( binary ? "colmap_binary" : "colmap_text" );
    const std::vector<std::string> parts = fuzz::splitParts( data, size, 5 );
    const char *names[5] = { "cameras", "images", "points3D", "rigs", "frames" };
    const std::filesystem::path model = folder / "model";
    std::filesystem::create_directories( model );
    for ( int i = 0; i < 5; ++i )
    {
      // an empty part after the first two stands for a model without that file (allowed)
      if ( i >= 2 && parts[i].empty() )
        continue;
      fuzz::writeBytes( model / ( std::string( names[i] ) + ( binary ? ".bin" : ".txt" ) ), reinterpret_cast<const std::uint8_t *>( parts[i].data() ), parts[i].size() );
    }

    ColmapModel read;
    try
    {
      read = ColmapModel::read( model );
    }
    catch ( const geostation::ColmapFormatError &error )
    {
      fuzz::requireMessage( error );
      return 0;
    }

    fuzz::outcome( "read: " + std::to_string( read.cameras.size() ) + " cameras, " + std::to_string( read.images.size() ) + " images, " + std::to_string( read.points3D.size() ) + " points, "
                   + std::to_string( read.rigs.size() ) + " rigs, " + std::to_string( read.frames.size() ) + " frames" );
    // written and read again, the model writes the same files
    const std::filesystem::path first = folder / "first";
    const std::filesystem::path second = folder / "second";
    read.writeText( first );
    ColmapModel again;
    try
    {
      again = ColmapModel::read( first );
    }
    catch ( const geostation::ColmapFormatError &error )
    {
      fuzz::violated( std::string( "a model that was read and written does not read back: " ) + error.what() );
    }
    again.writeText( second );
    for ( const char *name : names )
    {
      const std::string file = std::string( name ) + ".txt";
      if ( std::filesystem::exists( first / file ) != std::filesystem::exists( second / file ) )
        fuzz::violated( file + " is written on one round trip and not on the other" );
      if ( std::filesystem::exists( first / file ) )
        requireSameFile( first / file, second / file, "changes on its second round trip" );
    }
    if ( binary )
    {
      read.writeBinary( folder / "binary" );
      const ColmapModel fromBinary = ColmapModel::read( folder / "binary" );
      fromBinary.writeText( folder / "frombinary" );
      for ( const char *name : names )
      {
        const std::string file = std::string( name ) + ".txt";
        if ( std::filesystem::exists( first / file ) != std::filesystem::exists( folder / "frombinary" / file ) )
          fuzz::violated( file + " is written by one of the text and binary round trips only" );
        if ( std::filesystem::exists( first / file ) )
          requireSameFile( first / file, folder / "frombinary" / file, "differs between the text and the binary round trip" );
      }
    }

    geostation::ColmapImportOptions options;
    options.crs = "EPSG:25832";
    options.requireImageFiles = false;
    try
    {
      const geostation::BlockImportSummary import = geostation::importColmapModel( read, model, options );
      fuzz::outcome( "imported: " + std::to_string( import.block.images.size() ) + " images, " + std::to_string( import.tiePoints.size() ) + " tie points" );
      for ( const auto &image : import.block.images )
      {
        if ( !import.block.findCamera( image.cameraId ) )
          fuzz::violated( "an imported image without its camera: " + image.id );
        if ( !import.block.findStation( image.stationId ) )
          fuzz::violated( "an imported image without its station: " + image.id );
      }
    }
    catch ( const std::invalid_argument &error )
    {
      fuzz::requireMessage( error );
    }
    return 0;
  }
}

GEOSTATION_FUZZ_TARGET( colmap_text )
{
  return runColmapModel( data, size, false );
}

GEOSTATION_FUZZ_TARGET( colmap_binary )
{
  return runColmapModel( data, size, true );
}

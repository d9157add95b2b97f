/***************************************************************************
  fuzzsupport.cpp - files and checks shared by the fuzz targets
 ***************************************************************************/
#include "fuzztarget.h"

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <map>

#include <unistd.h>

namespace geostation::fuzz
{
  namespace
  {
    //! This process's folder of scratch files, removed when it exits.
    const std::filesystem::path &processFolder()
    {
      // RAM-backed where the system has it: the readers take file paths, and a run makes thousands of files a second
      static const std::filesystem::path folder =
        ( std::filesystem::exists( "/dev/shm" ) ? std::filesystem::path( "/dev/shm" ) : std::filesystem::temp_directory_path() ) / ( "geostation-fuzz-" + std::to_string( ::getpid() ) );
      static const bool removedAtExit = [] {
        return std::atexit( [] {
          std::error_code ignored;
          std::filesystem::remove_all( folder, ignored );
        } ) == 0;
      }();
      ( void )removedAtExit;
      return folder;
    }
  }

  std::filesystem::path scratchFolder( const std::string &name )
  {
    const std::filesystem::path folder = processFolder() / name;
    std::error_code ignored;
    std::filesystem::remove_all( folder, ignored );
    std::filesystem::create_directories( folder );
    return folder;
  }

  void writeBytes( const std::filesystem::path &file, const std::uint8_t *data, std::size_t size )
  {
    std::ofstream out( file, std::ios::binary | std::ios::trunc );
    out.write( reinterpret_cast<const char *>( data ), static_cast<std::streamsize>( size ) );
    if ( !out )
      throw std::runtime_error( "cannot write " + file.string() );
  }

  std::vector<std::string> splitParts( const std::uint8_t *data, std::size_t size, std::size_t count )
  {
    std::vector<std::string> parts( count );
    const std::string text( reinterpret_cast<const char *>( data ), size );
    std::size_t part = 0;
    std::size_t start = 0;
    while ( start <= text.size() )
    {
      std::size_t end = text.find( '\n', start );
      const bool last = end == std::string::npos;
      if ( last )
        end = text.size();
      const std::string line = text.substr( start, end - start );
      if ( line == "%%" && part + 1 < count )
      {
        // the line end before the separator belongs to it
        if ( !parts[part].empty() && parts[part].back() == '\n' )
          parts[part].pop_back();
        ++part;
      }
      else
        parts[part] += last ? line : line + '\n';
      if ( last )
        break;
      start = end + 1;
    }
    return parts;
  }

  void violated( const std::string &what )
  {
    std::fprintf( stderr, "fuzz property violated: %s\n", what.c_str() );
    std::fflush( stderr );
    std::abort();
  }

  namespace
  {
    bool gVerbose = false;
  }

  void requireMessage( const std::exception &error )
  {
    if ( std::strlen( error.what() ) == 0 )
      violated( "a documented failure without a message" );
    outcome( std::string( "rejected: " ) + error.what() );
  }

  void outcome( const std::string &what )
  {
    if ( gVerbose )
      std::fprintf( stderr, "  %s\n", what.c_str() );
  }

  void setVerbose( bool verbose )
  {
    gVerbose = verbose;
  }
}

namespace
{
  std::map<std::string, geostation::fuzz::Entry> &registry()
  {
    static std::map<std::string, geostation::fuzz::Entry> targets;
    return targets;
  }
}

geostation::fuzz::Registration::Registration( const char *name, Entry entry )
{
  registry()[name] = entry;
}

geostation::fuzz::Entry geostation::fuzz::findTarget( const std::string &name )
{
  const auto found = registry().find( name );
  return found == registry().end() ? nullptr : found->second;
}

std::vector<std::string> geostation::fuzz::targetNames()
{
  std::vector<std::string> names;
  for ( const auto &target : registry() )
    names.push_back( target.first );
  return names;
}

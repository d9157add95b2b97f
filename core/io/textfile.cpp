/***************************************************************************
  textfile.cpp - text outputs written whole or not at all, CSV fields
 ***************************************************************************/
#include "io/textfile.h"

#include <fstream>
#include <stdexcept>

namespace geostation
{

  void writeTextFileAtomically( const std::filesystem::path &file, const std::string &text, const std::string &what )
  {
    const std::string named = ( what.empty() ? std::string() : what + " " ) + file.string();
    std::filesystem::path temporary = file;
    temporary += ".tmp-write";
    {
      std::ofstream out( temporary, std::ios::binary | std::ios::trunc );
      if ( !out )
        throw std::runtime_error( "cannot write " + named + ": the folder is missing or not writable" );
      out << text;
      out.flush();
      if ( !out )
      {
        out.close();
        std::error_code ignored;
        std::filesystem::remove( temporary, ignored );
        throw std::runtime_error( "writing " + named + " failed (disk full?); the previous file is unchanged" );
      }
    }
    std::error_code ec;
    std::filesystem::rename( temporary, file, ec );
    if ( ec )
    {
      std::filesystem::remove( temporary, ec );
      throw std::runtime_error( "cannot replace " + named + ": " + ec.message() );
    }
  }

  std::string asciiLower( std::string text )
  {
    for ( char &c : text )
      if ( c >= 'A' && c <= 'Z' )
        c = static_cast<char>( c - 'A' + 'a' );
    return text;
  }

  std::string csvField( const std::string &value )
  {
    if ( value.find_first_of( ",\"\n\r" ) == std::string::npos )
      return value;
    std::string quoted = "\"";
    for ( char c : value )
    {
      if ( c == '"' )
        quoted += '"';
      quoted += c;
    }
    return quoted + "\"";
  }

} // namespace geostation

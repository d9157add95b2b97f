/***************************************************************************
  colmapfiles.h - reading and writing COLMAP's model files (internal)
  -------------------------------------------------------------------------
  The cursor over a binary model file (little-endian, records counted and
  checked against the bytes left), the records of a text model file
  (comments and empty lines skipped, failures naming file and line), and
  the writers' open and close with their messages. Shared by the model's
  files (colmapmodel.cpp) and its rigs and frames (colmaprigs.cpp).
 ***************************************************************************/
#ifndef GEOSTATION_IO_INTERNAL_COLMAPFILES_H
#define GEOSTATION_IO_INTERNAL_COLMAPFILES_H

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <string>
#include <type_traits>

#include "io/colmapmodel.h"

namespace geostation::colmapfiles
{
  namespace fs = std::filesystem;

  inline std::string readWholeFile( const fs::path &file )
  {
    std::ifstream in( file, std::ios::binary );
    if ( !in )
      throw ColmapFormatError( "cannot open the COLMAP file " + file.string() );
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
  }

  class BinaryCursor
  {
    public:
      BinaryCursor( const fs::path &file )
        : mFile( file ), mData( readWholeFile( file ) ) {}

      template <typename T> T read( const char *what )
      {
        if ( mData.size() - mOffset < sizeof( T ) )
          throw ColmapFormatError( "the COLMAP file " + mFile.string() + " ends in the middle of " + what + " (truncated or not a COLMAP binary file)" );
        T value;
        std::memcpy( &value, mData.data() + mOffset, sizeof( T ) );
        mOffset += sizeof( T );
        if constexpr ( std::is_floating_point_v<T> )
          if ( !std::isfinite( value ) )
            throw ColmapFormatError( "the COLMAP file " + mFile.string() + " holds a value that is not a finite number in " + what );
        return value;
      }

      std::string readString( const char *what )
      {
        const size_t end = mData.find( '\0', mOffset );
        if ( end == std::string::npos )
          throw ColmapFormatError( "the COLMAP file " + mFile.string() + " ends in the middle of " + what + " (truncated or not a COLMAP binary file)" );
        std::string s = mData.substr( mOffset, end - mOffset );
        mOffset = end + 1;
        return s;
      }

      //! A record count (stored as CountType), checked against the bytes left so that a corrupt count cannot allocate gigabytes.
      template <typename CountType = std::uint64_t> std::uint64_t readCount( size_t minRecordBytes, const char *what )
      {
        const std::uint64_t n = read<CountType>( what );
        if ( minRecordBytes > 0 && n > ( mData.size() - mOffset ) / minRecordBytes )
          throw ColmapFormatError( "the COLMAP file " + mFile.string() + " declares " + std::to_string( n ) + " " + what + " but is too short for them (truncated or not a COLMAP binary file)" );
        return n;
      }

      bool atEnd() const { return mOffset == mData.size(); }
      const fs::path &file() const { return mFile; }

    private:
      fs::path mFile;
      std::string mData;
      size_t mOffset = 0;
  };

  class TextLines
  {
    public:
      explicit TextLines( const fs::path &file )
        : mFile( file ), mIn( readWholeFile( file ) ) {}

      //! The next line that is neither empty nor a comment; false at the end.
      bool nextRecord( std::string &line )
      {
        while ( nextLine( line ) )
        {
          const size_t first = line.find_first_not_of( " \t\r" );
          if ( first != std::string::npos && line[first] != '#' )
            return true;
        }
        return false;
      }

      //! The very next line, empty or not (images.txt's point lines may be empty).
      bool nextLine( std::string &line )
      {
        if ( !std::getline( mIn, line ) )
          return false;
        ++mLineNumber;
        if ( !line.empty() && line.back() == '\r' )
          line.pop_back();
        return true;
      }

      [[noreturn]] void fail( const std::string &problem ) const
      {
        throw ColmapFormatError( "the COLMAP file " + mFile.string() + ", line " + std::to_string( mLineNumber ) + ": " + problem );
      }

    private:
      fs::path mFile;
      std::istringstream mIn;
      int mLineNumber = 0;
  };

  template <typename T> T parseField( std::istringstream &fields, const TextLines &lines, const char *what )
  {
    T value;
    if ( !( fields >> value ) )
      lines.fail( std::string( "expected " ) + what );
    return value;
  }

  inline std::ofstream openForWriting( const fs::path &file, bool binary )
  {
    std::ofstream out( file, binary ? std::ios::binary : std::ios::out );
    if ( !out )
      throw std::runtime_error( "cannot write " + file.string() + ": the folder is missing or not writable" );
    if ( !binary )
      out << std::setprecision( 17 );
    return out;
  }

  inline void finish( std::ofstream &out, const fs::path &file )
  {
    out.close();
    if ( !out )
      throw std::runtime_error( "writing " + file.string() + " failed (disk full?)" );
  }

  template <typename T> void put( std::ofstream &out, T value )
  {
    out.write( reinterpret_cast<const char *>( &value ), sizeof( T ) );
  }

} // namespace geostation::colmapfiles

#endif // GEOSTATION_IO_INTERNAL_COLMAPFILES_H

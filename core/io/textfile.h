/***************************************************************************
  textfile.h - text outputs written whole or not at all, CSV fields
 ***************************************************************************/
#ifndef GEOSTATION_IO_TEXTFILE_H
#define GEOSTATION_IO_TEXTFILE_H

#include <filesystem>
#include <string>

namespace geostation
{

  /**
   * Writes `text` to a temporary file beside `file` and renames it into
   * place, so a failure never leaves a half-written file (and the previous
   * file is unchanged). Throws std::runtime_error with one sentence, in
   * which `what` names the file's kind (e.g. "the block file").
   */
  void writeTextFileAtomically( const std::filesystem::path &file, const std::string &text, const std::string &what = "" );

  //! The text with ASCII letters in lower case (names matched case-insensitively).
  std::string asciiLower( std::string text );

  //! A CSV field, quoted (RFC 4180) when it holds a comma, a quote or a line break.
  std::string csvField( const std::string &value );

} // namespace geostation

#endif // GEOSTATION_IO_TEXTFILE_H

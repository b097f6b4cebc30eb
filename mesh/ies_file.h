// IES photometric files (ANSI/IESNA LM-63, the 1986, 1991, 1995 and 2002 editions: their headers differ, their
// data do not), read into an IntensityProfile (mesh/intensity_profile.h) of luminous intensity [cd]:
//   - an optional first line "IESNA:LM-63-2002" and keyword lines "[KEYWORD] text": read past;
//   - "TILT=NONE"; or "TILT=INCLUDE" and its table (lamp geometry, count, angles, factors): read and checked, not
//     applied; or "TILT=<file>": not read. The tilt factors correct a lamp burning at another tilt than it was
//     measured at; the baker takes every lamp to burn as measured;
//   - then numbers, separated by blanks, commas or line ends:
//       lamps, lumens per lamp (-1 for absolute photometry), candela multiplier, vertical angle count, horizontal
//       angle count, photometric type (1 = type C, the only one read: types A and B, 3 and 2, are for
//       floodlights and vehicle lamps), units type (1 feet, 2 metres), width, length and height of the luminous
//       opening (not used: the light is a point);
//       ballast factor, ballast-lamp photometric factor (1995; "future use", 1, since 2002), input watts;
//       the vertical angles [deg], increasing within [0, 180];
//       the horizontal angles [deg], increasing, 0 to 0, 90, 180 or up to 360 (symmetries), or 90 to 270;
//       the candela values, for each horizontal angle one per vertical angle.
// I = value x candela multiplier x ballast factor x ballast-lamp factor [cd].
// Untrusted input: every count is checked against the numbers that follow before anything is allocated. An
// InputError names file:line and what is wrong: no "TILT=" line, a malformed or non-finite number, too few
// numbers for the counts, a negative candela value or factor, angles out of order or range, an unknown symmetry,
// another photometric type.
#pragma once

#include <string>

#include "mesh/intensity_profile.h"

namespace pb {

IntensityProfile LoadIesFile(const std::string& path);

}  // namespace pb

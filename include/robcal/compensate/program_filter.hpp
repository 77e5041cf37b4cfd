#pragma once
/// \file
/// Program filtering moved to the vendor-language stage (robcal/programs/); this path stays
/// for the Python bindings until they include the new one.
#include "robcal/programs/program_filter.hpp"

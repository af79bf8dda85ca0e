#include "dlo/app/app_main.h"

#include <exception>
#include <iostream>
#include <string>

namespace dlo {

int runApp(const char* name, const std::function<int()>& body) {
  try {
    return body();
  } catch (const UsageError& e) {
    std::cerr << name << ": " << e.what() << "\n";
    return 2;
  } catch (const Error& e) {
    std::cerr << name << ": " << e.what() << "\n";
    return 1;
  } catch (const std::exception& e) {
    std::string what = e.what();
    what = what.substr(0, what.find('\n'));
    std::cerr << name << ": unexpected error: " << what << "\n";
    return 1;
  } catch (...) {
    std::cerr << name << ": unexpected error of unknown type.\n";
    return 1;
  }
}

}  // namespace dlo

// flipper dds security init DIR | add DIR NAME [--namespace NS]..., in the dds front-end module
// (frontend_module.hpp): the DDS Security keystore of apps/dds/keystore.hpp.
#include <iostream>

#include "commands.hpp"
#include "common.hpp"
#include "flipper/dds/keystore.hpp"
#include "flipper/sdk/errors.hpp"

namespace flipper::cli {

int dds_security_main(const std::string& action, const DdsSecurityArgs& args) {
  try {
    if (action == "init") {
      dds::init_keystore(args.dir, std::cout);
      std::cout << "next: flipper dds security add " << args.dir
                << " NAME (one per site or robot)\n";
    } else {
      dds::add_identity(args.dir, args.name, args.namespaces, std::cout);
      std::cout << "use: --set dds.security.keystore=" << args.dir
                << " --set dds.security.identity=" << args.name << "\n";
    }
    return kExitOk;
  } catch (const sdk::Error& e) {
    return report_error("dds security " + action, e.code(), e.what(), status_for(e.code()));
  }
}

}  // namespace flipper::cli

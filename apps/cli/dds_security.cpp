// flipper dds security init | add | request | sign | renew | revoke | install | export, in the dds
// front-end module (frontend_module.hpp): the DDS Security keystore of apps/dds/keystore.hpp and
// lab_keys.hpp.
#include <iostream>

#include "commands.hpp"
#include "common.hpp"
#include "flipper/dds/keystore.hpp"
#include "flipper/dds/lab_keys.hpp"
#include "flipper/sdk/errors.hpp"

namespace flipper::cli {

int dds_security_main(const std::string& action, const DdsSecurityArgs& args) {
  const std::string use = "use: --set dds.security.keystore=" + args.dir;
  try {
    if (action == "init") {
      dds::init_keystore(args.dir, std::cout);
      std::cout << "next: flipper dds security add " << args.dir
                << " NAME (one per site or robot), or sign " << args.dir
                << " NAME.csr (a lab's request)\n";
    } else if (action == "add") {
      dds::add_identity(args.dir, args.name, args.role, args.namespaces, args.days, std::cout);
      std::cout << use << " --set dds.security.identity=" << args.name << "\n";
    } else if (action == "request") {
      const std::string csr = dds::request_identity(args.dir, args.name, std::cout);
      std::cout << "next: send " << csr << " to the CA (flipper dds security sign CA_DIR " << csr
                << "); the key stays here\n";
    } else if (action == "sign") {
      const std::string name =
          dds::sign_request(args.dir, args.file, args.role, args.namespaces, args.days, std::cout);
      std::cout << "next, at the lab: flipper dds security install LAB_DIR " << name
                << " OUTBOX (this outbox/" << name << " folder, copied there)\n";
    } else if (action == "renew") {
      dds::renew_identity(args.dir, args.name, args.days, std::cout);
      std::cout << "next, at the lab: flipper dds security install LAB_DIR " << args.name
                << " OUTBOX, then restart its flipper\n";
    } else if (action == "revoke") {
      const std::string crl = dds::revoke_identity(args.dir, args.name, std::cout);
      std::cout << "next: copy " << crl
                << " into every lab's keystore folder (or point dds.security.crl at it) and "
                   "restart their flipper\n";
    } else if (action == "export") {
      dds::export_enclave(args.dir, args.name, args.file, args.enclave, std::cout);
      std::cout << "use: ROS_SECURITY_KEYSTORE=" << args.file << " and --ros-args --enclave "
                << args.enclave << " (a ROS 2 node), or --set dds.security.keystore=" << args.file
                << " --set dds.security.enclave=" << args.enclave << "\n";
    } else {
      dds::install_identity(args.dir, args.name, args.file, std::cout);
      std::cout << use << " --set dds.security.identity=" << args.name << "\n";
    }
    return kExitOk;
  } catch (const sdk::Error& e) {
    return report_error("dds security " + action, e.code(), e.what(), status_for(e.code()));
  }
}

}  // namespace flipper::cli

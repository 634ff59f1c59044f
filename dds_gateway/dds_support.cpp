#include "dds_gateway/dds_support.hpp"

#include <fstream>

#include <dds/security/dds_security_api_defs.h>

#ifndef HG_DDS_CONFIG_DIR
#error "HG_DDS_CONFIG_DIR must name dds_gateway/config"
#endif

namespace hg::dds_gateway {

bool SecurityFiles::any() const {
  return !(identity_ca.empty() && identity_certificate.empty() && private_key.empty() && permissions_ca.empty() &&
           governance.empty() && permissions.empty());
}

std::string SecurityFiles::problem() const {
  const std::pair<const char*, const std::string*> files[] = {
      {"identity CA", &identity_ca},        {"identity certificate", &identity_certificate},
      {"private key", &private_key},        {"permissions CA", &permissions_ca},
      {"governance document", &governance}, {"permissions document", &permissions}};
  for (const auto& [what, path] : files) {
    if (path->empty()) return std::string("DDS Security needs all six files; the ") + what + " is not given";
    std::ifstream in(*path);
    if (!in) return std::string("cannot read the ") + what + " '" + *path + "'";
  }
  return "";
}

std::string shipped_cyclone_config() { return std::string(HG_DDS_CONFIG_DIR) + "/cyclonedds-lo.xml"; }

Qos state_qos() {
  Qos q(dds_create_qos());
  dds_qset_reliability(q.get(), DDS_RELIABILITY_RELIABLE, DDS_SECS(1));
  dds_qset_durability(q.get(), DDS_DURABILITY_TRANSIENT_LOCAL);
  dds_qset_history(q.get(), DDS_HISTORY_KEEP_LAST, 1);
  return q;
}

Qos stream_qos() {
  Qos q(dds_create_qos());
  dds_qset_reliability(q.get(), DDS_RELIABILITY_RELIABLE, DDS_SECS(1));
  dds_qset_durability(q.get(), DDS_DURABILITY_VOLATILE);
  dds_qset_history(q.get(), DDS_HISTORY_KEEP_ALL, 0);
  return q;
}

namespace {
std::string why(dds_return_t rc) { return std::string(dds_strretcode(rc)); }
std::string file_uri(const std::string& path) { return "file:" + path; }
}  // namespace

dds_entity_t make_participant(dds_domainid_t domain, const std::string& cyclone_config, const SecurityFiles& security) {
  if (!cyclone_config.empty()) {
    dds_entity_t d = dds_create_domain(domain, cyclone_config.c_str());
    // PRECONDITION_NOT_MET: this process made the domain already (with its configuration).
    if (d < 0 && d != DDS_RETCODE_PRECONDITION_NOT_MET)
      throw DdsError("cannot create DDS domain " + std::to_string(domain) + " with configuration '" + cyclone_config +
                     "': " + why(d));
  }
  Qos qos(dds_create_qos());
  if (security.any()) {
    if (std::string p = security.problem(); !p.empty()) throw DdsError(p);
    // The plugins Debian ships in /usr/lib/<arch>/libddsc0debian/ (libddsc looks there by name).
    dds_qset_prop(qos.get(), DDS_SEC_PROP_AUTH_LIBRARY_PATH, "dds_security_auth");
    dds_qset_prop(qos.get(), DDS_SEC_PROP_AUTH_LIBRARY_INIT, "init_authentication");
    dds_qset_prop(qos.get(), DDS_SEC_PROP_AUTH_LIBRARY_FINALIZE, "finalize_authentication");
    dds_qset_prop(qos.get(), DDS_SEC_PROP_CRYPTO_LIBRARY_PATH, "dds_security_crypto");
    dds_qset_prop(qos.get(), DDS_SEC_PROP_CRYPTO_LIBRARY_INIT, "init_crypto");
    dds_qset_prop(qos.get(), DDS_SEC_PROP_CRYPTO_LIBRARY_FINALIZE, "finalize_crypto");
    dds_qset_prop(qos.get(), DDS_SEC_PROP_ACCESS_LIBRARY_PATH, "dds_security_ac");
    dds_qset_prop(qos.get(), DDS_SEC_PROP_ACCESS_LIBRARY_INIT, "init_access_control");
    dds_qset_prop(qos.get(), DDS_SEC_PROP_ACCESS_LIBRARY_FINALIZE, "finalize_access_control");
    dds_qset_prop(qos.get(), DDS_SEC_PROP_AUTH_IDENTITY_CA, file_uri(security.identity_ca).c_str());
    dds_qset_prop(qos.get(), DDS_SEC_PROP_AUTH_IDENTITY_CERT, file_uri(security.identity_certificate).c_str());
    dds_qset_prop(qos.get(), DDS_SEC_PROP_AUTH_PRIV_KEY, file_uri(security.private_key).c_str());
    dds_qset_prop(qos.get(), DDS_SEC_PROP_ACCESS_PERMISSIONS_CA, file_uri(security.permissions_ca).c_str());
    dds_qset_prop(qos.get(), DDS_SEC_PROP_ACCESS_GOVERNANCE, file_uri(security.governance).c_str());
    dds_qset_prop(qos.get(), DDS_SEC_PROP_ACCESS_PERMISSIONS, file_uri(security.permissions).c_str());
  }
  dds_entity_t p = dds_create_participant(domain, qos.get(), nullptr);
  if (p < 0)
    throw DdsError("cannot create a DDS participant on domain " + std::to_string(domain) +
                   (security.any() ? " with DDS Security (certificates or signed documents rejected?)" : "") + ": " +
                   why(p));
  return p;
}

dds_entity_t make_topic(dds_entity_t participant, const dds_topic_descriptor_t* desc, const std::string& name) {
  dds_entity_t t = dds_create_topic(participant, desc, name.c_str(), nullptr, nullptr);
  if (t < 0) throw DdsError("cannot create DDS topic '" + name + "': " + why(t));
  return t;
}

dds_entity_t make_writer(dds_entity_t participant, dds_entity_t topic, const dds_qos_t* qos) {
  dds_entity_t w = dds_create_writer(participant, topic, qos, nullptr);
  if (w < 0) throw DdsError("cannot create a DDS writer: " + why(w));
  return w;
}

dds_entity_t make_reader(dds_entity_t participant, dds_entity_t topic, const dds_qos_t* qos) {
  dds_entity_t r = dds_create_reader(participant, topic, qos, nullptr);
  if (r < 0) throw DdsError("cannot create a DDS reader: " + why(r));
  return r;
}

}  // namespace hg::dds_gateway

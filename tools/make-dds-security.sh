#!/usr/bin/env bash
# Makes a complete DDS Security set for hg-dds-gateway with openssl: an identity CA, a permissions CA,
# identity certificates, and governance and permissions documents signed (S/MIME) by the permissions CA.
# For tests and for a first install; a plant with its own PKI supplies the same files (docs/dds_gateway.md).
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/version.sh"
hg_answer_version make-dds-security "$@"

usage() {
  cat <<'USAGE'
usage: tools/make-dds-security.sh [--prefix P] [--days N] [--force] OUTDIR
Writes into OUTDIR:
  identity_ca.pem  identity_ca.key          CA that signs every participant's identity certificate
  permissions_ca.pem permissions_ca.key     CA that signs governance and permissions documents
  governance.xml   governance.p7s           domains 0..230: no unauthenticated participants, join access
                                            control, discovery/liveliness/metadata/data ENCRYPTED, read and
                                            write access control on every topic
  NAME.pem NAME.key NAME_permissions.xml NAME_permissions.p7s   for each identity:
     gateway   publishes every P* topic except Pjob_request, subscribes Pjob_request
     plant     publishes Pjob_request, subscribes every P* topic (an MES / line controller)
     observer  subscribes Phealth only (a dashboard): may neither read the outline nor send jobs
  rogue/   the same names made by a second, untrusted pair of CAs (for tests: a participant the
           gateway must not authenticate)
Options:
  --prefix P   DDS topic prefix (default hg_, as hg-dds-gateway --dds-topic-prefix)
  --days N     certificate and permission validity (default 3650)
  --force      overwrite an existing set in OUTDIR (default: refuse)
Private keys are written unencrypted with mode 600; keep OUTDIR private.
USAGE
}

prefix=hg_
days=3650
force=0
out=''
while [[ $# -gt 0 ]]; do
  case "$1" in
    --help|-h) usage; exit 0 ;;
    --prefix) prefix="${2:?--prefix needs a value}"; shift 2 ;;
    --days) days="${2:?--days needs a value}"; shift 2 ;;
    --force) force=1; shift ;;
    -*) echo "make-dds-security: unknown option '$1' (see --help)" >&2; exit 2 ;;
    *) [[ -z "$out" ]] || { echo "make-dds-security: only one OUTDIR" >&2; exit 2; }; out="$1"; shift ;;
  esac
done
[[ -n "$out" ]] || { usage >&2; exit 2; }
[[ "$prefix" =~ ^[A-Za-z0-9_/]*$ ]] || { echo "make-dds-security: prefix '$prefix' has characters other than letters, digits, _ and /" >&2; exit 2; }
[[ "$days" =~ ^[0-9]+$ ]] || { echo "make-dds-security: --days '$days' is not a number" >&2; exit 2; }
command -v openssl >/dev/null || { echo "make-dds-security: openssl not found (apt-get install openssl)" >&2; exit 1; }
if [[ -e "$out/identity_ca.pem" && $force -eq 0 ]]; then
  echo "make-dds-security: $out already holds a set (use --force to replace it)" >&2; exit 1
fi

umask 077
not_before=$(date -u +%Y-%m-%dT%H:%M:%S -d '1 day ago')
not_after=$(date -u +%Y-%m-%dT%H:%M:%S -d "$days days")

# make_ca DIR NAME CN
make_ca() {
  openssl ecparam -name prime256v1 -genkey -noout -out "$1/$2.key"
  openssl req -new -x509 -sha256 -days "$days" -key "$1/$2.key" -out "$1/$2.pem" -subj "/O=hullgrind/CN=$3" \
    -addext basicConstraints=critical,CA:TRUE -addext keyUsage=critical,keyCertSign,cRLSign,digitalSignature
}

# make_identity DIR NAME : key and certificate signed by DIR/identity_ca
make_identity() {
  openssl ecparam -name prime256v1 -genkey -noout -out "$1/$2.key"
  openssl req -new -sha256 -key "$1/$2.key" -out "$1/$2.csr" -subj "/O=hullgrind/CN=$2"
  openssl x509 -req -sha256 -days "$days" -in "$1/$2.csr" -CA "$1/identity_ca.pem" -CAkey "$1/identity_ca.key" \
    -CAcreateserial -out "$1/$2.pem" 2>/dev/null
  rm -f "$1/$2.csr"
}

# sign DIR FILE.xml -> FILE.p7s, S/MIME signed by DIR/permissions_ca
sign() {
  openssl smime -sign -text -in "$1/$2.xml" -out "$1/$2.p7s" -signer "$1/permissions_ca.pem" \
    -inkey "$1/permissions_ca.key"
}

governance() {
  cat <<XML
<?xml version="1.0" encoding="UTF-8"?>
<dds xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance"
     xsi:noNamespaceSchemaLocation="http://www.omg.org/spec/DDS-SECURITY/20170901/omg_shared_ca_governance.xsd">
  <domain_access_rules>
    <domain_rule>
      <domains><id_range><min>0</min><max>230</max></id_range></domains>
      <allow_unauthenticated_participants>false</allow_unauthenticated_participants>
      <enable_join_access_control>true</enable_join_access_control>
      <discovery_protection_kind>ENCRYPT</discovery_protection_kind>
      <liveliness_protection_kind>ENCRYPT</liveliness_protection_kind>
      <rtps_protection_kind>NONE</rtps_protection_kind>
      <topic_access_rules>
        <topic_rule>
          <topic_expression>*</topic_expression>
          <enable_discovery_protection>true</enable_discovery_protection>
          <enable_liveliness_protection>true</enable_liveliness_protection>
          <enable_read_access_control>true</enable_read_access_control>
          <enable_write_access_control>true</enable_write_access_control>
          <metadata_protection_kind>ENCRYPT</metadata_protection_kind>
          <data_protection_kind>ENCRYPT</data_protection_kind>
        </topic_rule>
      </topic_access_rules>
    </domain_rule>
  </domain_access_rules>
</dds>
XML
}

# topics_xml TOPIC... -> <topics> element
topics_xml() {
  printf '<topics>'
  for t in "$@"; do printf '<topic>%s</topic>' "$t"; done
  printf '</topics>'
}

# permissions NAME PUBLISH_TOPICS SUBSCRIBE_TOPICS (space-separated; empty: none)
permissions() {
  local name=$1 rules='' pub sub
  read -ra pub <<<"$2"  # split on spaces; read never expands the * of a topic pattern
  read -ra sub <<<"$3"
  [[ ${#pub[@]} -gt 0 ]] && rules+="<publish>$(topics_xml "${pub[@]}")</publish>"
  [[ ${#sub[@]} -gt 0 ]] && rules+="<subscribe>$(topics_xml "${sub[@]}")</subscribe>"
  cat <<XML
<?xml version="1.0" encoding="UTF-8"?>
<dds xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance"
     xsi:noNamespaceSchemaLocation="http://www.omg.org/spec/DDS-SECURITY/20170901/omg_shared_ca_permissions.xsd">
  <permissions>
    <grant name="${name}_grant">
      <subject_name>CN=${name},O=hullgrind</subject_name>
      <validity><not_before>${not_before}</not_before><not_after>${not_after}</not_after></validity>
      <allow_rule>
        <domains><id_range><min>0</min><max>230</max></id_range></domains>
        ${rules}
      </allow_rule>
      <default>DENY</default>
    </grant>
  </permissions>
</dds>
XML
}

p=$prefix
gateway_pub="${p}outline ${p}part_pose ${p}grind_path ${p}job_status ${p}robot_status ${p}health"

# make_set DIR LABEL
make_set() {
  local dir=$1
  mkdir -p "$dir"
  make_ca "$dir" identity_ca "hullgrind $2 identity CA"
  make_ca "$dir" permissions_ca "hullgrind $2 permissions CA"
  governance >"$dir/governance.xml"
  sign "$dir" governance
  make_identity "$dir" gateway
  permissions gateway "$gateway_pub" "${p}job_request" >"$dir/gateway_permissions.xml"
  make_identity "$dir" plant
  permissions plant "${p}job_request" "${p}*" >"$dir/plant_permissions.xml"
  make_identity "$dir" observer
  permissions observer "" "${p}health" >"$dir/observer_permissions.xml"
  for n in gateway plant observer; do sign "$dir" "${n}_permissions"; done
  rm -f "$dir"/*.srl
}

[[ $force -eq 1 ]] && rm -rf "$out/rogue"
make_set "$out" trusted
make_set "$out/rogue" rogue
chmod 600 "$out"/*.key "$out"/rogue/*.key
echo "make-dds-security: DDS Security set in $out (gateway, plant, observer; rogue/ is untrusted)"

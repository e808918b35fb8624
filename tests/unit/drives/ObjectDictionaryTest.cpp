// The emulated drive's object dictionary, and the EDS shipped for it: the same objects, types,
// access and defaults, so users comparing their drive's EDS compare with what runs.
#include "host_sim/drives/ObjectDictionary.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <map>
#include <set>
#include <string>

namespace carril::sim {
namespace {

constexpr std::uint8_t kNode = 5;

using Section = std::map<std::string, std::string>;

// An EDS (INI syntax): section name (upper case) -> key -> value; comments dropped.
std::map<std::string, Section> read_eds(const std::string& path) {
  std::map<std::string, Section> out;
  std::ifstream in(path);
  std::string line, current;
  while (std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty() || line[0] == ';') continue;
    if (line[0] == '[') {
      current = line.substr(1, line.find(']') - 1);
      for (char& c : current) c = char(std::toupper(static_cast<unsigned char>(c)));
      out[current];
      continue;
    }
    const auto eq = line.find('=');
    if (eq != std::string::npos) out[current][line.substr(0, eq)] = line.substr(eq + 1);
  }
  return out;
}

std::string section_name(const ObjectDictionary& od, const OdEntry& e) {
  int subs = 0;
  for (std::size_t i = 0; i < od.size(); ++i) subs += od.entry(i).index == e.index;
  char buf[16];
  if (subs == 1 && e.subindex == 0) {
    std::snprintf(buf, sizeof buf, "%04X", e.index);
  } else {
    std::snprintf(buf, sizeof buf, "%04XSUB%X", e.index, e.subindex);
  }
  return buf;
}

TEST(ObjectDictionaryTest, TheEdsDescribesExactlyTheImplementedObjects) {
  const auto eds =
      read_eds(std::string(CARRIL_SOURCE_DIR) + "/config/drives/carril_emulated_drive.eds");
  ASSERT_FALSE(eds.empty()) << "config/drives/carril_emulated_drive.eds not found";
  const ObjectDictionary od(kNode);
  std::set<std::string> listed;  // the indices named in the object lists
  for (const char* list : {"MANDATORYOBJECTS", "OPTIONALOBJECTS", "MANUFACTUREROBJECTS"}) {
    ASSERT_TRUE(eds.count(list)) << list;
    for (const auto& [key, value] : eds.at(list)) {
      if (key != "SupportedObjects") listed.insert(value);
    }
  }
  std::set<std::string> indices;
  for (std::size_t i = 0; i < od.size(); ++i) {
    const OdEntry& e = od.entry(i);
    const std::string name = section_name(od, e);
    char index[8];
    std::snprintf(index, sizeof index, "0x%04X", e.index);
    indices.insert(index);
    ASSERT_TRUE(eds.count(name)) << "no section [" << name << "] for " << e.name;
    const Section& s = eds.at(name);
    char type[8];
    std::snprintf(type, sizeof type, "0x%04X", unsigned(e.type));
    EXPECT_EQ(s.at("DataType"), type) << name;
    EXPECT_EQ(s.at("AccessType"), od_access_name(e.access)) << name;
    EXPECT_EQ(s.at("PDOMapping"), e.pdo_mappable ? "1" : "0") << name;
    EXPECT_EQ(s.at("ObjectType"), "0x7") << name;
    // $NODEID+x defaults are node-relative: evaluated for this node, they are the value.
    std::string dv = s.at("DefaultValue");
    std::uint32_t want = 0;
    if (dv.rfind("$NODEID", 0) == 0) {
      EXPECT_TRUE(e.node_relative) << name;
      want = kNode + (dv.size() > 8 ? std::stoul(dv.substr(8), nullptr, 0) : 0UL);
    } else {
      EXPECT_FALSE(e.node_relative) << name;
      want = std::uint32_t(std::stoul(dv, nullptr, 0));
    }
    EXPECT_EQ(e.value, want) << name << " DefaultValue=" << dv;
  }
  EXPECT_EQ(listed, indices);
  std::size_t vars = 0;
  for (const auto& [name, s] : eds) vars += s.count("ObjectType") && s.at("ObjectType") == "0x7";
  EXPECT_EQ(vars, od.size());  // and nothing more
}

TEST(ObjectDictionaryTest, ResetsRestoreDefaultsByArea) {
  ObjectDictionary od(kNode);
  EXPECT_EQ(od.get(0x1800, 1), 0x180U + kNode);
  od.set(0x1017, 0, 50);
  od.set(0x6083, 0, 7);
  od.reset_communication();
  EXPECT_EQ(od.get(0x1017, 0), 0U);
  EXPECT_EQ(od.get(0x6083, 0), 7U);
  od.reset_all();
  EXPECT_EQ(od.get(0x6083, 0), 40960U);
}

TEST(ObjectDictionaryTest, FindsObjectsAndKeepsValuesToTheirSize) {
  ObjectDictionary od(kNode);
  EXPECT_EQ(od.find(0x2000, 0), nullptr);
  EXPECT_FALSE(od.has_index(0x2000));
  EXPECT_EQ(od.find(0x1018, 7), nullptr);
  EXPECT_TRUE(od.has_index(0x1018));
  od.set(0x6060, 0, 0xFFFFFF03U);  // int8: only the low byte
  EXPECT_EQ(od.get(0x6060, 0), 0x03U);
  od.set(0x6040, 0, 0x1234567FU);
  EXPECT_EQ(od.get(0x6040, 0), 0x567FU);
  EXPECT_EQ(od_size(OdType::Integer32), 4);
}

}  // namespace
}  // namespace carril::sim

#include <gtest/gtest.h>

#include "config/port_table.hpp"
#include "model_description.hpp"

TEST(ModelDescription, ListsEveryVariableAndEveryOutputInModelStructure) {
  auto t = config::parse_port_table(
      "$FMU_SETTINGS\nmodel, m\ntimestep, 1e-5\n$FMU_HOPSAN_PORTS\n1, cav, Hydraulic\n"
      "$FMU_HOPSAN_SEND\n1, p\n$FMU_HOPSAN_RECEIVE\n1, q\n1, x\n",
      "p.cfg");
  std::string xml = fmugen::model_description_xml(t, "a <test> & more");
  EXPECT_NE(xml.find("fmiVersion=\"2.0\""), std::string::npos);
  EXPECT_NE(xml.find("guid=\"" + config::fmu_guid(t) + "\""), std::string::npos);
  EXPECT_NE(xml.find("modelIdentifier=\"m\""), std::string::npos);
  EXPECT_NE(xml.find("a &lt;test&gt; &amp; more"), std::string::npos);
  EXPECT_NE(xml.find("name=\"cav.p\" valueReference=\"0\" causality=\"input\""), std::string::npos);
  EXPECT_NE(xml.find("name=\"cav.x\" valueReference=\"2\" causality=\"output\""), std::string::npos);
  // Outputs are variables 2 and 3 (1-based) and must appear in Outputs and InitialUnknowns.
  size_t outputs = xml.find("<Outputs>"), initial = xml.find("<InitialUnknowns>");
  ASSERT_NE(outputs, std::string::npos);
  ASSERT_NE(initial, std::string::npos);
  EXPECT_NE(xml.find("<Unknown index=\"3\"/>", outputs), std::string::npos);
  EXPECT_NE(xml.find("<Unknown index=\"3\"/>", initial), std::string::npos);
  EXPECT_EQ(xml.find("<Unknown index=\"1\"/>"), std::string::npos) << "an input is not an output";
  // A default experiment an importer can run as is: 1000 coupling steps of the
  // table's step, in the shortest digits that read back exactly (not %.17g's
  // 1.0000000000000001e-05).
  EXPECT_NE(xml.find("<DefaultExperiment startTime=\"0\" stopTime=\"0.01\" stepSize=\"1e-05\"/>"),
            std::string::npos)
      << xml.substr(xml.find("<DefaultExperiment"), 120);
}

// Each FMU says what it is: the --description given, else the port table's
// own (free text, commas kept), else one made from its ports.
TEST(ModelDescription, TheDescriptionComesFromTheOptionThenTheTableThenItsPorts) {
  const std::string ports =
      "$FMU_HOPSAN_PORTS\n1, chamber_A, Hydraulic\n2, piston, Mechanic\n"
      "$FMU_HOPSAN_SEND\n1, p\n$FMU_HOPSAN_RECEIVE\n1, q\n2, x\n";
  auto plain = config::parse_port_table("$FMU_SETTINGS\nmodel, m\ntimestep, 2.5e-6\n" + ports, "p.cfg");
  auto own = config::parse_port_table(
      "$FMU_SETTINGS\nmodel, m\ndescription, The piston, its collar and the tool\ntimestep, 2.5e-6\n" + ports, "q.cfg");
  auto described = [](const std::string& xml) {
    const size_t at = xml.find("description=\"") + 13;
    return xml.substr(at, xml.find('"', at) - at);
  };
  EXPECT_EQ(described(fmugen::model_description_xml(plain, "")),
            "m: fe_server co-simulation, hydraulic port chamber_A, mechanic port piston (pressure coupling, 2.5e-06 s)");
  EXPECT_EQ(described(fmugen::model_description_xml(own, "")), "The piston, its collar and the tool");
  EXPECT_EQ(described(fmugen::model_description_xml(own, "given")), "given");
  EXPECT_EQ(own.hash(), plain.hash()) << "the description is not part of what both sides must agree on";
  const auto xml = fmugen::model_description_xml(plain, "", {"fmugen 9.9", "2026-12-03T14:00:00Z"});
  EXPECT_NE(xml.find("generationTool=\"fmugen 9.9\" generationDateAndTime=\"2026-12-03T14:00:00Z\""),
            std::string::npos);
}

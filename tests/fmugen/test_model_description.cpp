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
  // A default experiment an importer can run as is: 1000 coupling steps of the table's step.
  EXPECT_NE(xml.find("<DefaultExperiment startTime=\"0\" stopTime=\"0.01\" stepSize=\"1.0000000000000001e-05\"/>"),
            std::string::npos)
      << xml.substr(xml.find("<DefaultExperiment"), 120);
}

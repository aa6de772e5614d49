within Bicycle.Interfaces;
connector RealOutput = output Real "Connector of a Real output signal (as Modelica.Blocks.Interfaces.RealOutput)";

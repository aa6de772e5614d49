within Bicycle.Interfaces;
connector RealInput = input Real "Connector of a Real input signal (as Modelica.Blocks.Interfaces.RealInput)";

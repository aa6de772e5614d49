within Bicycle.Control;
block Proportional "The paper's rider: steer torque proportional to roll, T = -k*phi"
  extends Bicycle.Icons.Block;
  parameter Real k(unit = "N.m/rad") = 10 "Gain from roll angle to steer torque";
  Bicycle.Interfaces.RealInput phi(final quantity = "Angle", final unit = "rad", displayUnit = "deg") "Roll angle, positive leaning to the right"
    annotation(Placement(transformation(extent = {{-140, -20}, {-100, 20}})));
  Bicycle.Interfaces.RealOutput T(final quantity = "Torque", final unit = "N.m") "Steer torque"
    annotation(Placement(transformation(extent = {{100, -10}, {120, 10}})));
equation
  T = -k*phi;
  annotation(
    Icon(graphics = {
      Text(extent = {{-90, 40}, {90, -30}}, textString = "T = -k φ", textColor = {0, 0, 0}),
      Text(extent = {{-150, -150}, {150, -110}}, textString = "k=%k", textColor = {0, 0, 0})}),
    __Cosim(export = true),
    Documentation(info = "<html>
<p>Input (<a href=\"modelica://Bicycle.Interfaces.RealInput\">RealInput</a>): <code>phi</code> (roll
angle, rad); output (<a href=\"modelica://Bicycle.Interfaces.RealOutput\">RealOutput</a>):
<code>T</code> (steer torque, N.m). The FMU has the same input and output names. Modelica twin of
the Python block <code>Proportional</code> (<code>cosim.cosimulation.controllers</code>).</p>
<p>The rider of the paper: with the Whipple family, connect <code>bike.phi</code> to
<code>phi</code> and <code>T</code> to <code>bike.T_delta</code>
(Examples.WhippleLinearRiderPush).</p>
</html>"));
end Proportional;

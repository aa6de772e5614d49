within Bicycle;
package Rider "Rider models: neuromuscular delay (twins of cosim's Python delay blocks)"
  extends Bicycle.Icons.Package;
  annotation(Documentation(info = "<html>
<p>The rider's neuromuscular delay as a block with one
<a href=\"modelica://Bicycle.Interfaces.RealInput\">RealInput</a> <code>u</code> and one
<a href=\"modelica://Bicycle.Interfaces.RealOutput\">RealOutput</a> <code>y</code> (no unit: the
delay passes any signal, steer torque or lean angle). It is connected between a controller and
the bicycle, e.g. <code>connect(controller.T, delay.u); connect(delay.y, bicycle.T_delta)</code>.</p>
<p><code>PadeDelay</code> is the Modelica twin of the Python blocks <code>PadeDelay</code> (same
approximation) and <code>TransportDelay</code> (the exact delay, which the compiler cannot express:
no <code>delay()</code>); its FMU has the input <code>u</code> and the output <code>y</code>.</p>
</html>"));
end Rider;

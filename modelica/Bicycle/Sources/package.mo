within Bicycle;
package Sources "Signal sources for co-simulation systems (twins of cosim's Python sources)"
  extends Bicycle.Icons.SourcesPackage;
  annotation(Documentation(info = "<html>
<p>Sources have no input and one
<a href=\"modelica://Bicycle.Interfaces.RealOutput\">RealOutput</a> <code>y</code> (a torque in
N.m), connected to a torque input of a bicycle, e.g.
<code>connect(push.y, bike.T_phi)</code> for a lateral push.</p>
<p>They are stateless functions of time with jumps at <code>start</code> (and
<code>start + duration</code>) and no event handling: in a co-simulation the jumps are exact when
they fall on communication points; inside one model the error-controlled integrator shortens
its steps at a jump. <code>TorquePulse</code> and <code>TorqueStep</code> are the Modelica twins of
the Python blocks <code>Pulse</code> and <code>Step</code> (same parameters; output
<code>y</code>).</p>
</html>"));
end Sources;

within Bicycle.UsersGuide;
class Conventions "Axes, sign conventions, angles and units"
  extends Bicycle.Icons.Information;
  annotation(Documentation(info = "<html>
<h4>Two sign conventions</h4>
<p>The library keeps the conventions of the sources its models are checked against, so that every
number can be compared with the paper it comes from without conversion:</p>
<table border=\"1\" cellpadding=\"3\">
<tr><th></th><th>second-order models (<code>Bicycles.InvertedPendulum</code>, <code>SelfStabilizing</code>,
<code>SelfStabilizingGyro</code>, <code>RearSteered</code>, <code>LeaningRider</code>,
<code>CrownedRoller</code>, the paper's eqs (1)-(27))</th>
<th>Whipple family (<code>Bicycles.Whipple</code>, <code>WhippleRider</code>, <code>WhippleLinear</code>;
Meijaard et al. 2007)</th></tr>
<tr><td>axes</td><td>ISO 8855: x forward, y left, z up</td><td>x forward, y right, z down</td></tr>
<tr><td>roll angle phi</td><td>positive leaning right</td><td>positive leaning right (same)</td></tr>
<tr><td>steer angle delta</td><td>positive steering <b>left</b></td><td>positive steering <b>right</b></td></tr>
<tr><td>steer torque</td><td>positive tending to steer left</td><td>positive tending to steer right</td></tr>
<tr><td>yaw angle psi</td><td>positive turning left</td><td>positive turning right</td></tr>
<tr><td>vertical coordinates</td><td>heights h positive up</td><td>z of a centre of mass negative above the ground</td></tr>
</table>
<p>So a steer angle (and a steer torque) of the Whipple family is minus the one of the second-order
models; roll angles agree. <code>RearSteered</code> is model (1) driven backwards, seen by its rider:
x points in the direction of motion, so its forward speed is <code>V &gt; 0</code> and the table holds
for it as for the other second-order models (<code>V &lt; 0</code>: ridden backwards).</p>
<h4>Head angle and steer-axis tilt</h4>
<p>The paper's head angle <code>lambda</code> (Figure 1) is the angle between the steer axis and the
ground, about 70&deg;. The Whipple family uses Meijaard's steer-axis tilt <code>lam</code>, the angle
between the steer axis and the vertical: <code>lam = pi/2 - lambda</code> (pi/10 for the benchmark
bicycle). Trail <code>c</code> is positive when the front contact point is behind the point where the
steer axis meets the ground in both.</p>
<h4>Wheels</h4>
<p>A wheel's radius <code>r</code> is the height of its centre above the ground when upright, for every
wheel model. A toroidal tyre has the crown (tube) radius <code>t</code>; <code>t = 0</code> is the knife
edge. The crowned roller of the paper's eq (27) is the same geometry with a large lateral radius.
Wheel angles are measured about the axle, which points to the right, so rolling forward is a
<b>negative</b> wheel rate in the Whipple family: forward speed <code>v = -u_R*rR</code> when upright.</p>
<h4>Units</h4>
<p>SI throughout (<code>Bicycle.Units</code>, the definitions of <code>Modelica.Units.SI</code>):
m, kg, kg.m2, rad, s. Inertia-tensor elements <code>I*xz</code> are tensor elements (the product of
inertia with a minus sign), as in Meijaard et al. (2007), Table 1.</p>
</html>"));
end Conventions;

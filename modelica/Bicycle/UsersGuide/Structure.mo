within Bicycle.UsersGuide;
class Structure "The packages and how the components connect"
  annotation(Documentation(info = "<html>
<h4>Packages</h4>
<table border=\"1\" cellpadding=\"3\">
<tr><td><code>Bicycles</code></td><td>the paper's bicycles, exported as FMUs: the second-order models
(eqs (1)-(27)), the linear Whipple model (24) and the nonlinear Whipple bicycle (26) with and without
the leaning rider</td></tr>
<tr><td><code>Mechanics</code></td><td>multibody components in generalized coordinates (Kane's
method as components): the <code>Frame</code> and <code>ContactRows</code> connectors, rigid bodies,
joints, the rear frame, steer axis and front frame, the rider's upper body on a hip hinge, and the
<code>Ground</code> root</td></tr>
<tr><td><code>Wheels</code></td><td>replaceable wheels: knife edge, torus, crowned roller</td></tr>
<tr><td><code>Linear</code></td><td>the bodies of the linear Whipple model (24), each contributing its
part of M, C1, K0, K2</td></tr>
<tr><td><code>Components</code></td><td>parts of the second-order models (rear frame, static and
gyroscopic front fork, crowned rollers, leaning upper body, path kinematics)</td></tr>
<tr><td><code>Records</code></td><td>data sets (packages of constants) generated from
<code>cosim/params/*.toml</code>: the benchmark bicycle, the paper's bicycle with and without rider,
the rider split, the second-order models' parameters</td></tr>
<tr><td><code>Control</code>, <code>Rider</code>, <code>Sources</code></td><td>controllers, the rider's
delay and test signals, with <code>Interfaces.RealInput</code>/<code>RealOutput</code> connectors</td></tr>
<tr><td><code>Examples</code></td><td>bicycles connected to controllers, delays and sources</td></tr>
</table>
<h4>How the nonlinear bicycle is assembled</h4>
<p>Each body's motion is described by its <code>Mechanics.Interfaces.Frame</code> connector as a
function of the generalized coordinates and speeds: orientation, position, angular velocity and
velocity with their partial derivatives with respect to the speeds (potential variables). Each body
returns its generalized mass matrix and generalized forces (flow variables), so a
<code>connect()</code> sums them as Kane's equations require. Joints pass the kinematics on and add
the partial angular velocity of their own speed. A wheel adds the rolling-contact rows
(<code>ContactRows</code>: the velocity of the contact point as a linear function of the speeds, and
its acceleration remainder). <code>Ground</code>, which the bicycle extends, owns the coordinates
and the independent speeds, eliminates the dependent speeds with the front contact's rows and writes
Kane's reduced equations <code>Mr der(u_i) = f_r</code>; the pitch is solved from the holonomic
constraint at initialization. The result is an index-1 model, linear in the accelerations, which the
compiler turns into an explicit ODE with exact derivatives.</p>
</html>"));
end Structure;

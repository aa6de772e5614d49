within Bicycle.UsersGuide;
class Structure "The packages and how the components connect"
  extends Bicycle.Icons.Information;
  annotation(Documentation(info = "<html>
<h4>Packages</h4>
<table border=\"1\" cellpadding=\"3\">
<tr><td><code>Bicycles</code></td><td>the paper's bicycles, exported as FMUs: the second-order models
(eqs (1)-(27)), the linear Whipple model (24) and the nonlinear Whipple bicycle (26) with and without
the leaning rider; the three Whipple models extend <code>PartialWhippleParameters</code>, the 26
parameters of Meijaard's Table 1</td></tr>
<tr><td><code>Mechanics</code></td><td>multibody components in generalized coordinates (Kane's
method as components): the frame and contact connectors, rigid bodies, joints that own their
coordinates, the rear frame, steer axis and front frame, the rider's upper body on a hip hinge, and
the <code>Ground</code></td></tr>
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
<tr><td><code>Icons</code></td><td>the icons the packages, examples, blocks and components extend
(partial classes with nothing but an <code>Icon</code> annotation, as <code>Modelica.Icons</code>)</td></tr>
</table>
<h4>Icons and diagrams</h4>
<p>Every connector, model and block has an icon (its own or one it extends from <code>Icons</code>):
the connectors those of the Modelica Standard Library (<code>Frame_a</code>/<code>Frame_b</code> of
MultiBody, <code>RealInput</code>/<code>RealOutput</code> of Blocks; the roll axis a circle, the steer
axis a diamond, the wheel's contact a tyre's footprint, the ground's a hatched square,
<code>RollSteer_a</code>/<code>_b</code> filled and open squares), each component a picture of what it
is. Every model that connects components has a diagram: the bicycles read as the side view of the
paper's Figure 1, the ground at the bottom, the rear wheel left, the front wheel right, the rear
frame, steer axis and front frame between them, the rider's hip hinge and upper body above; in the
examples the controllers and sources stand left of the bicycle.</p>
<h4>How the nonlinear bicycle is assembled</h4>
<p><img src=\"modelica://Bicycle/Resources/Images/Whipple.svg\" width=\"800\"
alt=\"The diagram of Bicycle.Bicycles.Whipple: ground, rear wheel, rear frame, steer axis, front frame, front wheel\"/></p>
<p>The diagram of <a href=\"modelica://Bicycle.Bicycles.Whipple\">Whipple</a> (drawn from its
annotations by <code>cosim diagram Bicycle.Bicycles.Whipple</code>): the ground at the bottom carries the rear wheel, whose
hub carries the rear frame; the steer axis joins the rear frame to the front frame, which carries
the front wheel; both wheels' contacts go back to the ground, and the two torque inputs drive the
steer axis and the roll of the rear frame. The diagrams of the other bicycles and of the examples
are in <code>Resources/Images</code>.</p>
<p>Each body's motion is described by its frame connector
(<code>Mechanics.Interfaces.Frame_a</code>, <code>Frame_b</code>) as a function of the generalized
speeds: orientation, position, angular velocity and velocity with their partial derivatives with
respect to the speeds and the acceleration remainders. These travel causally, from the ground
outwards (<code>output</code> on the ground's side, <code>input</code> on the body's side). Three
acausal pairs make the connector balanced: the generalized speeds with the speeds the joints own,
the generalized accelerations with the generalized forces, and gravity with energy. Each body
returns its generalized active and inertia forces, written with the generalized accelerations, so a
<code>connect()</code> sums them as Kane's equations require. A joint owns its coordinate (angle and
rate are its states), adds the partial angular velocity of its own speed and reports its speed; the
assembly tells it its column <code>k</code> and says the number of speeds <code>n</code> once. A
wheel adds the rolling-contact rows (<code>WheelContact</code>: the velocity of the contact point as
a linear function of the speeds, and its acceleration remainder). <code>Ground</code>, a component
like the others, owns the rear frame's position and attitude, eliminates the dependent speeds with
the front contact's rows and states Kane's reduced equations <code>T'(sum of F) = 0</code>, which the
compiler solves for the independent accelerations (a linear system of three or four unknowns); the
pitch is solved from the holonomic constraint at initialization. The result is an index-1 model,
linear in the accelerations, which the compiler turns into an explicit ODE with exact
derivatives. The bicycle names its states (<code>delta = steer.angle</code>, ...); the compiler gives
each state the top-level name of its alias, so the FMU's variables are those of the paper.</p>
</html>"));
end Structure;

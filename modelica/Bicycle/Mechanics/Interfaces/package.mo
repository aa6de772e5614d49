within Bicycle.Mechanics;
package Interfaces "Connectors of the generalized-coordinate multibody components"
  annotation(Documentation(info = "<html><p><code>Frame</code>: a body-fixed coordinate system with its
kinematics in terms of the generalized speeds, and the generalized inertia and forces of the bodies
beyond it as flows. <code>ContactRows</code>: the velocity-constraint rows of a rolling contact.</p></html>"));
end Interfaces;

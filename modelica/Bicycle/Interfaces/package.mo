within Bicycle;
package Interfaces "Connectors between bicycle components"
  extends Bicycle.Icons.InterfacesPackage;
end Interfaces;
